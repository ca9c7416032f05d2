"""``vc-serve``: bundles on live cameras as a service — frames in, tracked people out as MQTT events, health and
metrics over HTTP, faults survived (docs/serve.md)."""
