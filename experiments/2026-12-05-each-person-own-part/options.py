"""Four ways to cut people's crops for a bundle's keypoint model, on TUD-Stadtmitte's frames (every 6th): the time the
model takes a frame and how far the keypoints it is sure of move between a person read alone and beside the others
(frozen experiment, decision 0059).

    PYTHONPATH=src python experiments/2026-12-05-each-person-own-part/options.py BUNDLE >> RESULTS/options.jsonl

- shared: one part of the frame reaching every crop, one call (and one for the mirrors): the runtime before 0059.
- whole: the whole frame, one call (and one for the mirrors).
- own: each person's own part, one call each (and one for their mirror): the runtime since 0059.
- stacked: each person's own part and its mirror stacked as frames of one call, the graph's frame index taken from
  the roi's number (graph surgery on the bundle's model: what a re-export would ship).
"""

from __future__ import annotations

import json
import sys
import time
from pathlib import Path

import numpy as np
import onnx
import onnxruntime as ort
from onnx import TensorProto, helper

from vc.deploy.crop_pose import MAPS_OUTPUT, PEAK_FLOOR, keypoints_of_maps, mirrored_back, worth_reading
from vc.deploy.engines import onnxruntime_inference
from vc.deploy.facing import FRAME_INPUT, ROIS_INPUT, crop_rois, frame_part, mirrored, own_parts
from vc.deploy.frames import FrameRange, FrameSource
from vc.deploy.runtime import Runtime

FRAMES = Path("../shared/data/tud_stadtmitte/frames")
REPEATS = 3


def stacked_graph(model: bytes) -> bytes:
    """The keypoint model taking many frames, roi i cut from frame i mod frames."""
    graph = onnx.load_from_string(model)
    frame_dim = graph.graph.input[0].type.tensor_type.shape.dim[0]
    frame_dim.ClearField("dim_value")
    frame_dim.dim_param = "frames"
    nodes = [node for node in graph.graph.node if node.op_type != "ConstantOfShape"]
    at = next(index for index, node in enumerate(nodes) if node.op_type == "RoiAlign")
    index_nodes = [helper.make_node("Range", ["zero", "count", "one_step"], ["roi_number"]),
                   helper.make_node("Shape", [FRAME_INPUT], ["frame_shape"]),
                   helper.make_node("Gather", ["frame_shape", "zero"], ["frames"], axis=0),
                   helper.make_node("Mod", ["roi_number", "frames"], ["frame_index"])]
    graph.graph.initializer.append(helper.make_tensor("one_step", TensorProto.INT64, [], [1]))
    del graph.graph.node[:]
    graph.graph.node.extend(nodes[:at] + index_nodes + nodes[at:])
    return graph.SerializeToString()


class Options:
    def __init__(self, model: bytes) -> None:
        self.session = onnxruntime_inference(model, 1)
        options = ort.SessionOptions()
        options.intra_op_num_threads = options.inter_op_num_threads = 1
        self.stacked_session = ort.InferenceSession(stacked_graph(model), options, providers=["CPUExecutionProvider"])

    def _maps(self, part: np.ndarray, rois: np.ndarray, session: ort.InferenceSession | None = None) -> np.ndarray:
        return np.asarray((session or self.session).run([MAPS_OUTPUT], {FRAME_INPUT: part, ROIS_INPUT: rois})[0])

    def shared(self, frame: np.ndarray, rois: np.ndarray) -> np.ndarray:
        part, shifted = frame_part(frame, rois)
        return (self._maps(part, shifted) + mirrored_back(self._maps(*mirrored(part, shifted)))) / 2

    def whole(self, frame: np.ndarray, rois: np.ndarray) -> np.ndarray:
        return (self._maps(frame[None], rois) + mirrored_back(self._maps(*mirrored(frame[None], rois)))) / 2

    def own(self, frame: np.ndarray, rois: np.ndarray) -> np.ndarray:
        return np.concatenate([(self._maps(*part) + mirrored_back(self._maps(*mirror))) / 2 for part, mirror in
                               zip(own_parts(frame, rois), own_parts(frame, rois, mirror=True), strict=True)])

    def stacked(self, frame: np.ndarray, rois: np.ndarray) -> np.ndarray:
        inputs = list(own_parts(frame, rois)) + list(own_parts(frame, rois, mirror=True))
        height, width = (max(part.shape[axis] for part, _ in inputs) for axis in (1, 2))
        parts = np.zeros((len(inputs), height, width, 3), np.uint8)
        for index, (part, _) in enumerate(inputs):
            parts[index, :part.shape[1], :part.shape[2]] = part[0]
        maps = self._maps(parts, np.concatenate([roi for _, roi in inputs]), self.stacked_session)
        return (maps[:len(rois)] + mirrored_back(maps[len(rois):])) / 2


def main() -> None:
    bundle = Path(sys.argv[1])
    runtime = Runtime(bundle, threads=1)
    options = Options(runtime.bundle.crop_pose)
    names = ("shared", "whole", "own", "stacked")
    seconds = {name: 0.0 for name in names}
    moved = {name: [] for name in names}
    people = frames = 0
    for frame in FrameSource(FRAMES, FrameRange(1, 179, 6)):
        image = frame.image
        boxes = np.array([person.box for person in runtime(image) if not person.weak]).reshape(-1, 4)
        boxes = boxes[worth_reading(boxes)]
        frames += 1
        if not len(boxes):
            continue
        people += len(boxes)
        rois = crop_rois(boxes)
        for name in names:
            read = getattr(options, name)
            start = time.perf_counter()
            for _ in range(REPEATS):
                together = keypoints_of_maps(read(image, rois), rois)
            seconds[name] += (time.perf_counter() - start) / REPEATS
            alone = np.concatenate([keypoints_of_maps(read(image, rois[k:k + 1]), rois[k:k + 1])
                                    for k in range(len(rois))])
            sure = (together[..., 2] >= PEAK_FLOOR) | (alone[..., 2] >= PEAK_FLOOR)
            heights = np.repeat((boxes[:, 3] - boxes[:, 1])[:, None], 17, axis=1)
            moved[name].append((np.hypot(*(together[..., :2] - alone[..., :2]).transpose(2, 0, 1)) / heights)[sure])
    runtime.close()
    result = {"bundle": str(bundle), "frames": frames, "people": people}
    for name in names:
        shares = np.concatenate(moved[name])
        result[name] = {"ms_a_frame": round(1000 * seconds[name] / frames, 2),
                        "sure_keypoints": int(shares.size),
                        "moved_over_1pct_height": round(float((shares > 0.01).mean()), 4),
                        "moved_over_3pct_height": round(float((shares > 0.03).mean()), 4),
                        "most_moved_share_of_height": round(float(shares.max()), 3)}
    print(json.dumps(result), flush=True)


if __name__ == "__main__":
    main()
