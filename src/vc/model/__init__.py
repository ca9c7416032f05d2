"""ScenePoseNet, target encoding, the dataset reader, training, metrics and ONNX export (docs/design.md, "Model")."""
