"""A compiled bundle run end to end on full frames it has never seen, before anyone deploys it.

A full test frame is the scene's background with the people of one held-out render of every region pasted in at
their place: each render is resized back to its crop window and its people's pixels (instance mask, grown by a
pixel for the anti-aliased edge) replace the background's, far regions first. The ground truth is their amodal
boxes in frame pixels. Through the runtime (crops, onnxruntime, decoding, ownership, mapping to the frame) this
checks everything the per-region evaluation cannot: that the bundle's regions together find each person once,
where the frame shows them. The empty background is run too: what it reports there is false alarms.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

import cv2
import numpy as np

from vc.deploy.areas import in_area
from vc.deploy.runtime import Runtime
from vc.evaluation.draw import draw_people
from vc.evaluation.metrics import ImageResult, evaluate
from vc.evaluation.renders import asked_for
from vc.io import read_image, write_image
from vc.render.dataset import RegionData, open_region, read_manifest, read_sample

if TYPE_CHECKING:  # the settings' module imports the training config, and with it torch
    from vc.stages.config import SelfTestSettings


@dataclass
class TestFrame:
    image: np.ndarray  # (H, W, 3) uint8
    truth_boxes: np.ndarray  # (N, 4) frame pixels
    truth_ignore: np.ndarray  # (N,) bool


def _to_frame(xy: np.ndarray, crop_window: list[int], input_size: list[int]) -> np.ndarray:
    """Region-input pixels -> frame pixels (pixel centres at integers), as the runtime maps them."""
    x0, y0, width, height = crop_window
    scale = np.array([input_size[0] / width, input_size[1] / height])
    return np.array([x0, y0]) + (np.asarray(xy, np.float64) + 0.5) / scale - 0.5


def composite_frame(background: np.ndarray, regions: list[RegionData], index: int) -> TestFrame:
    """Test frame ``index``: held-out sample ``index`` (modulo) of every region pasted into ``background``."""
    image = background.copy()
    boxes, ignore = [], []
    owned = [region.region["owned_image_area"] for region in regions]
    for region in regions:
        sample = region.held_out[index % len(region.held_out)]
        render, instances = read_sample(sample)
        x0, y0, width, height = region.region["crop_window"]
        people = cv2.dilate((instances > 0).astype(np.uint8), np.ones((3, 3), np.uint8))
        people = cv2.resize(people, (width, height), interpolation=cv2.INTER_NEAREST).astype(bool)
        crop = image[y0:y0 + height, x0:x0 + width]
        crop[people] = cv2.resize(render, (width, height), interpolation=cv2.INTER_LINEAR)[people]
        for annotation in sample.annotations:
            x, y, box_width, box_height = annotation["amodal_bbox"]
            corners = _to_frame(np.array([[x, y], [x + box_width, y + box_height]]), region.region["crop_window"],
                                region.region["input_size"])  # affine: outer edges map like pixel centres
            boxes.append(corners.ravel())
            foot = _to_frame(np.array(annotation["foot"]), region.region["crop_window"], region.region["input_size"])
            reportable = any(in_area(foot[None], area)[0] for area in owned)
            ignore.append(not (asked_for(annotation, tuple(region.region["input_size"])) and reportable))
    return TestFrame(image, np.array(boxes).reshape(-1, 4), np.array(ignore, bool))


@dataclass
class SelfTest:
    ap50: float
    frames: int
    people_asked_for: int
    ms_per_frame: float  # median, after a warm-up frame
    false_alarms_on_background: int
    frame: np.ndarray  # the test frame with the most people, as the camera would give it
    overlay: np.ndarray  # that frame drawn with what the bundle found there

    def to_dict(self) -> dict:
        return {"ap50": round(self.ap50, 4), "frames": self.frames, "people_asked_for": self.people_asked_for,
                "ms_per_frame": round(self.ms_per_frame, 2),
                "false_alarms_on_background": self.false_alarms_on_background}


def self_test(runtime: Runtime, background: np.ndarray, regions: list[RegionData], frames: int) -> SelfTest:
    false_alarms = len(runtime(background))  # also the warm-up
    results, milliseconds = [], []
    shown, overlay, most_people = None, None, -1
    for index in range(frames):
        frame = composite_frame(background, regions, index)
        start = time.perf_counter()
        people = runtime(frame.image)
        milliseconds.append((time.perf_counter() - start) * 1e3)
        results.append(ImageResult(frame.truth_boxes, np.array([p.box for p in people]).reshape(-1, 4),
                                   np.array([p.score for p in people]), truth_ignore=frame.truth_ignore))
        if (~frame.truth_ignore).sum() > most_people:
            most_people = int((~frame.truth_ignore).sum())
            shown, overlay = frame.image, draw_people(frame.image, people, truth_boxes=frame.truth_boxes)
    evaluation = evaluate(results)
    asked = int(sum((~r.truth_ignore).sum() for r in results))
    return SelfTest(evaluation.ap50, frames, asked, float(np.median(milliseconds)), false_alarms, shown, overlay)


def self_test_bundle(bundle: Path, renders: Path, background: Path, settings: SelfTestSettings,
                     overlay: Path | None = None, test_frame: Path | None = None) -> SelfTest:
    """The self-test stage: ``bundle`` on ``settings.frames`` frames composed of the held-out renders in
    ``renders`` on ``background``; with ``overlay``, the frame with the most people is written there drawn with what
    the bundle found, and with ``test_frame`` as it is (a frame to try the bundle on: ``vc-run``, ``vc-serve``)."""
    regions = [open_region(renders, name) for name in read_manifest(renders)["regions"]]
    with Runtime(bundle) as runtime:
        result = self_test(runtime, read_image(background), regions, settings.frames)
    if overlay is not None:
        write_image(overlay, result.overlay)
    if test_frame is not None:
        write_image(test_frame, result.frame)
    return result
