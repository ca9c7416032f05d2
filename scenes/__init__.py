"""Scene descriptions: the YAML schema and loader, layout geometry, region planning, bundled scenes."""
