"""ScenePoseNet, target encoding, the dataset reader, training, metrics and ONNX export (DESIGN.md "Model")."""
