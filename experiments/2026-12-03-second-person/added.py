"""The people the behind maps add on the held-out renders: matched or not, and what the unmatched ones lie on
(frozen experiment, issue 57 item 2).

    PYTHONPATH=../.. python added.py RUN RENDERS REGION PT [--threshold T]

Each decoded person not among the people decoded without the behind maps is an added one. Unmatched ones are told
apart by their best IoU with an annotated person: >= 0.5 with one already found (a second box for them), >= 0.5 with
one the evaluation ignores (less than half seen), else 0.3-0.5 (a box beside someone) or none.
"""

from __future__ import annotations

import argparse
from collections import Counter
from pathlib import Path

import numpy as np
import second_person as sp
import torch

from vc.calibration.camera import camera_from_dict
from vc.deploy.decode import DecodeConfig
from vc.deploy.heatmaps import FINE_CHANNELS
from vc.evaluation.metrics import evaluate
from vc.evaluation.renders import image_result
from vc.model.codec import expected_height_map
from vc.model.network import ScenePoseNet
from vc.model.trainer import load_checkpoint
from vc.render.dataset import open_region, read_sample


def _iou_matrix(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    top_left = np.maximum(a[:, None, :2], b[None, :, :2])
    bottom_right = np.minimum(a[:, None, 2:], b[None, :, 2:])
    inter = np.clip(bottom_right - top_left, 0, None).prod(axis=2)
    area = lambda boxes: (boxes[:, 2] - boxes[:, 0]) * (boxes[:, 3] - boxes[:, 1])  # noqa: E731
    return inter / (area(a)[:, None] + area(b)[None] - inter)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("run", type=Path)
    parser.add_argument("renders", type=Path)
    parser.add_argument("region")
    parser.add_argument("checkpoint", type=Path)
    parser.add_argument("--threshold", type=float, default=0.3)
    args = parser.parse_args()
    sp.install()
    sp.THRESHOLD[0] = args.threshold
    checkpoint = load_checkpoint(args.checkpoint)
    config: DecodeConfig = checkpoint.config.decode
    net = ScenePoseNet(checkpoint.config.network)
    net.load_state_dict(checkpoint.content["model"])
    net.eval()
    data = open_region(args.renders, args.region, checkpoint.config.held_out_fraction)
    heights = expected_height_map(camera_from_dict(data.region["camera"]), config.stride,
                                  load_checkpoint(args.run / "checkpoints" / f"{args.region}.pt")
                                  .content["reference_height_m"])
    kinds: Counter = Counter()
    results, added_flags, reaches, behind_lists, fronts = [], [], [], [], []
    fronts_behind: Counter = Counter()
    distances: dict[str, list[float]] = {}
    for sample in data.held_out:
        image, instances = read_sample(sample)
        with torch.no_grad():
            maps = net(torch.from_numpy(image[None]).permute(0, 3, 1, 2).float() / 255.0)["heatmaps"][0].numpy()
        base = sp._DECODE(maps[:FINE_CHANNELS], config, heights)
        people = sp.decode_behind(maps, config, heights)
        base_centres = [tuple(np.round(person.centre, 3)) for person in base]
        added_flags.append([tuple(np.round(person.centre, 3)) not in base_centres for person in people])
        base_xy = np.array([person.centre for person in base]).reshape(-1, 2)
        behind_lists.append(sp.behind_of(sample.annotations, instances))
        fronts.append([int(np.argmin(np.hypot(*(base_xy - person.centre).T))) if len(base_xy) else -1
                       for person in people])
        reaches.append([float(np.hypot(*(base_xy - person.centre).T).min(initial=np.inf)
                              / (person.box[3] - person.box[1])) for person in people])
        results.append(image_result(sample.annotations, instances, people, config.stride))
    evaluation = evaluate(results)
    for result, flags, reach, behind, front_of, matches in zip(results, added_flags, reaches, behind_lists, fronts,
                                                               evaluation.matches, strict=True):
        matched_truth = {truth: detection for truth, detection in matches}
        matched_detections = set(matched_truth.values())
        ious = _iou_matrix(np.asarray(result.boxes).reshape(-1, 4), np.asarray(result.truth_boxes).reshape(-1, 4))
        for index, added in enumerate(flags):
            if not added:
                continue
            if index in matched_detections:
                kinds["matched"] += 1
                distances.setdefault("matched", []).append(reach[index])
                continue
            best = int(np.argmax(ious[index])) if ious.shape[1] else -1
            best_iou = float(ious[index, best]) if best >= 0 else 0.0
            if best_iou >= 0.5 and result.truth_ignore[best]:
                kinds["on an ignored person"] += 1
            elif best_iou >= 0.5:
                kind = "a second box for a found person" if best in matched_truth else "on a person, not matched"
                kinds[kind] += 1
                if kind == "a second box for a found person":
                    front_truth = next((t for t, d in matches if d == front_of[index]), None)
                    behind_truth = None if front_truth is None else behind[front_truth]
                    fronts_behind["its front not matched" if front_truth is None else
                                  "no one behind its front" if behind_truth is None else
                                  "the one behind its front found" if behind_truth in matched_truth else
                                  "the one behind its front not found"] += 1
                distances.setdefault(kind, []).append(reach[index])
            elif best_iou >= 0.3:
                kinds["beside someone (IoU 0.3-0.5)"] += 1
            else:
                kinds["on no one"] += 1
    print(f"{args.region} threshold {args.threshold}: {sum(kinds.values())} added; " + ", ".join(
        f"{kind} {count}" for kind, count in kinds.most_common()))
    print("  second boxes: " + ", ".join(f"{kind} {count}" for kind, count in fronts_behind.most_common()))
    for kind, values in distances.items():
        print(f"  {kind}: nearest peak decoded without them at quartiles "
              + " / ".join(f"{q:.3f}" for q in np.quantile(values, [0.25, 0.5, 0.75])) + " of their box height")


if __name__ == "__main__":
    main()
