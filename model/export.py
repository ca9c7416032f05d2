"""A trained region network as an ONNX graph an appliance can run as is (DESIGN.md, "Bundle").

The graph takes the region's crop of the frame exactly as the camera delivers it — uint8, (1, crop height,
crop width, 3), RGB — and does the rest itself: resize to the network input (bilinear, half-pixel centres, as
``cv2.INTER_LINEAR`` made the training backgrounds), scale to [0, 1], the network, and returns the 19 heat maps
(1, 19, h, w). Shapes are fixed (one region, one crop window), opset 17, the classic TorchScript exporter
(no ``onnxscript`` needed); the network's config and the region travel as metadata.
"""

from __future__ import annotations

import io
import json

import onnx
import torch
import torch.nn.functional as F
from torch import Tensor, nn

from vc.model.network import ScenePoseNet

OPSET = 17
INPUT_NAME, OUTPUT_NAME = "crop", "heatmaps"


class DeployedNetwork(nn.Module):
    """uint8 NHWC crop -> heat maps: the preprocessing an appliance would otherwise have to reimplement."""

    def __init__(self, net: ScenePoseNet, input_size: tuple[int, int]) -> None:
        super().__init__()
        self.net, self.input_size = net.eval(), input_size

    def forward(self, crop: Tensor) -> Tensor:
        image = crop.permute(0, 3, 1, 2).float()
        width, height = self.input_size
        if tuple(image.shape[-2:]) != (height, width):
            image = F.interpolate(image, size=(height, width), mode="bilinear", align_corners=False, antialias=False)
        return self.net(image / 255.0)["heatmaps"]


def export_onnx(net: ScenePoseNet, crop_size: tuple[int, int], input_size: tuple[int, int],
                metadata: dict[str, object]) -> bytes:
    """The serialised ONNX model of ``net`` for crops of ``crop_size`` (width, height)."""
    wrapper = DeployedNetwork(net, input_size)
    example = torch.zeros(1, crop_size[1], crop_size[0], 3, dtype=torch.uint8)
    buffer = io.BytesIO()
    with torch.no_grad():
        torch.onnx.export(wrapper, (example,), buffer, input_names=[INPUT_NAME], output_names=[OUTPUT_NAME],
                          opset_version=OPSET, dynamo=False, do_constant_folding=True)
    model = onnx.load_from_string(buffer.getvalue())
    for key, value in metadata.items():
        entry = model.metadata_props.add()
        entry.key, entry.value = key, value if isinstance(value, str) else json.dumps(value)
    onnx.checker.check_model(model)
    return model.SerializeToString()
