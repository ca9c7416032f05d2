"""Scene descriptions: the YAML schema and loader, layout geometry, region planning.

The example scenes are data, not part of the package: ``examples/scenes/`` in the repository."""
