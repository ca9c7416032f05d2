"""Visual Compiler: compile one camera's scene into a pedestrian detector trained only on synthetic renders.

The subpackages, in the order a compile uses them:

- ``vc.scenes``: the scene description (YAML schema, loader, layout geometry, region planning);
- ``vc.calibration``: cameras, lens distortion, the camera's response, noise and compression, light from one image;
- ``vc.render``: synthetic people rendered by Mitsuba into each region's view, with exact labels;
- ``vc.model``: ScenePoseNet, its targets, training and ONNX export;
- ``vc.deploy``: the bundle and the appliance runtime (numpy and onnxruntime only: decoding, tracking);
- ``vc.evaluation``: metrics, the self-test, real-video evaluation beside reference detectors;
- ``vc.stages``: the stages as library functions with one typed compile config;
- ``vc.cli``: the commands, which only parse and report.
"""

__version__ = "0.1.0"
