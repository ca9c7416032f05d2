"""The bundle format, region map, heat-map decoding and the onnxruntime runtime.

Imports numpy and onnxruntime only: an appliance has no torch and no mitsuba (docs/design.md, "Bundle").
"""
