"""``vc-run``: a bundle on real frames, as an appliance would run it.

    vc-run BUNDLE INPUT -o OUT [--frames first:last:step] [--overlay] [--threads N] [--[no-]parallel-regions]
           [--fps F] [--no-tracking] [--unfit suppress|flag] [--engine onnxruntime|openvino] [--decoder c|numpy]
           [--public-key KEY.pub] [--quiet]

INPUT is an image, a folder of images or a video file. Writes ``OUT/detections.jsonl`` (one line per frame: its
number, name, scene fitness — state, the reason of an unfit one and the numbers measured, :mod:`vc.deploy.fitness`
— and people with box, score, 17 keypoints with confidences, mask area, the network's handedness and, when
tracked, the track, whether the person was carried by it unseen and what decided which way they face; on an unfit
frame under ``--unfit flag``, the frame's state), ``OUT/summary.json`` (frames, people, frames per fitness state,
milliseconds per frame, the engine and the decoder) and with ``--overlay`` the frames drawn with their detections
(``OUT/overlay.mp4`` for a video, ``OUT/overlays/<name>.png`` otherwise). OUT appears complete or not at all. Bad
input (a damaged bundle, an unreadable or empty video, frames of another size than the bundle's camera) prints
one ``error:`` line and exits with status 2.
"""

from __future__ import annotations

import argparse
import json
import time
from dataclasses import asdict
from pathlib import Path

import cv2
import numpy as np
from tqdm import tqdm

from vc import __version__
from vc.cli.common import fitness_line, handles_input_errors, positive_float, positive_int
from vc.deploy.engines import DEFAULT_ENGINE, ENGINES
from vc.deploy.frames import Frame, FrameRange, FrameSource
from vc.deploy.native import DECODERS
from vc.deploy.runtime import DEFAULT_UNFIT, UNFIT_SETTINGS, Runtime
from vc.deploy.tracking import Tracker, tracking_rate
from vc.errors import InputError
from vc.evaluation.draw import draw_people
from vc.io import atomic_directory, write_image, write_json

DETECTIONS, SUMMARY = "detections.jsonl", "summary.json"


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="vc-run", description=__doc__.split("\n\n")[0])
    parser.add_argument("--version", action="version", version=f"%(prog)s {__version__}")
    parser.add_argument("bundle", type=Path, help="a vc-export bundle (folder or zip)")
    parser.add_argument("input", type=Path, help="an image, a folder of images or a video file")
    parser.add_argument("-o", "--output", type=Path, required=True, help="output folder")
    parser.add_argument("--frames", type=FrameRange.parse, default=FrameRange(),
                        help="first:last:step, 1-based and inclusive (default: all)")
    parser.add_argument("--overlay", action="store_true", help="also write the frames drawn with their detections")
    parser.add_argument("--threads", type=positive_int, default=None, help="the engine's threads (default: all cores)")
    parser.add_argument("--engine", choices=ENGINES, default=DEFAULT_ENGINE,
                        help=f"what runs the regions' graphs (default {DEFAULT_ENGINE}; openvino: OpenVINO's CPU "
                             "plugin, pip install openvino)")
    parser.add_argument("--decoder", choices=DECODERS, default=None,
                        help="what turns heat maps into people (default: c where it is built, else numpy; the same "
                             "people: vc.deploy.native)")
    parser.add_argument("--public-key", type=Path, default=None, metavar="KEY.pub",
                        help="run the bundle only if its manifest is signed by this Ed25519 public key (PEM)")
    parser.add_argument("--parallel-regions", action=argparse.BooleanOptionalAction, default=None,
                        help="run the regions at once, one thread each (default: when there are several)")
    parser.add_argument("--fps", type=positive_float, default=None,
                        help="the input's frames per second (default: a video's own rate; a folder of frames is "
                             "tracked only when given): people are tracked, and their walking direction decides "
                             "which way they face (vc.deploy.tracking)")
    parser.add_argument("--no-tracking", action="store_true",
                        help="each frame on its own: no tracks, facing from appearance only")
    parser.add_argument("--unfit", choices=UNFIT_SETTINGS, default=DEFAULT_UNFIT,
                        help="the people of a frame the scene fitness finds dark, overexposed, blurred, moved or "
                             "changed: withheld (suppress, the default) or kept with the state (flag); a covered "
                             "frame never yields people")
    parser.add_argument("--quiet", action="store_true", help="no progress bar")
    return parser


class _Overlays:
    """Overlay frames as a video (video input) or one PNG per frame."""

    def __init__(self, folder: Path, source: FrameSource, frame_size: tuple[int, int]) -> None:
        self.folder, self.writer = folder, None
        if source.kind == "video":
            fps = source.fps / source.frames.step
            self.writer = cv2.VideoWriter(str(folder / "overlay.mp4"), cv2.VideoWriter_fourcc(*"mp4v"), fps,
                                          frame_size)
        else:
            (folder / "overlays").mkdir()

    def add(self, frame: Frame, image: np.ndarray) -> None:
        if self.writer is not None:
            self.writer.write(np.ascontiguousarray(image[:, :, ::-1]))
        else:
            write_image(self.folder / "overlays" / f"{Path(frame.name).stem}.png", image)

    def close(self) -> None:
        if self.writer is not None:
            self.writer.release()


@handles_input_errors
def main(argv: list[str] | None = None) -> int:
    args = _parser().parse_args(argv)
    source = FrameSource(args.input, args.frames)
    rate = None if args.no_tracking else tracking_rate(source, args.fps)
    tracker = Tracker() if rate else None
    with Runtime(args.bundle, threads=args.threads, parallel_regions=args.parallel_regions,
                 public_key=args.public_key, unfit=args.unfit, engine=args.engine,
                 decoder=args.decoder,
                 weak_people_above=tracker.config.weak_people_above if tracker else None) as runtime:
        width, height = runtime.bundle.frame_size
        milliseconds, people_count, coasted_count, fitnesses = [], 0, 0, []
        with atomic_directory(args.output) as staging, open(staging / DETECTIONS, "w") as lines:
            overlays = _Overlays(staging, source, (width, height)) if args.overlay else None
            try:
                for frame in tqdm(source, total=len(source), desc="vc-run", unit="frame", disable=args.quiet):
                    if frame.image.shape != (height, width, 3):
                        raise InputError(args.input, f"frame {frame.number} ({frame.name})",
                                         f"is {frame.image.shape[1]}x{frame.image.shape[0]}, the bundle's camera is "
                                         f"{width}x{height}")
                    start = time.perf_counter()
                    result = runtime.run(frame.image)
                    people = result.people
                    if tracker is not None:
                        people = result.reported(tracker.update(people, frame.number / rate, frame.image))
                    milliseconds.append((time.perf_counter() - start) * 1e3)
                    people_count += len(people)
                    coasted_count += sum(person.coasted for person in people)
                    fitnesses.append(result.fitness)
                    lines.write(json.dumps({"frame": frame.number, "name": frame.name,
                                            "fitness": result.fitness.to_dict(),
                                            "people": [person.to_dict() for person in people]}) + "\n")
                    if overlays:
                        overlays.add(frame, draw_people(frame.image, people))
            finally:
                if overlays:
                    overlays.close()
            summary = {
                "bundle": str(args.bundle), "scene": runtime.bundle.manifest["scene"], "input": str(args.input),
                "input_kind": source.kind, "frames": len(milliseconds), "people": people_count,
                "regions": [{"name": r.name, "precision": r.precision} for r in runtime.bundle.regions],
                "threads": args.threads, "parallel_regions": runtime.pool is not None, "engine": runtime.engine,
                "decoder": runtime.decoder,
                "tracking": ({"fps": rate, "config": asdict(tracker.config), "tracks": tracker.next_identity - 1,
                              "people_carried": coasted_count} if tracker else None),
                "fitness": runtime.fitness_summary(fitnesses),
                "ms_per_frame": {"mean": float(np.mean(milliseconds)), "median": float(np.median(milliseconds)),
                                 "p90": float(np.percentile(milliseconds, 90))},
            }
            write_json(staging / SUMMARY, summary)
    timing = summary["ms_per_frame"]
    print(f"vc-run: {summary['frames']} frame(s), {people_count} people, {timing['median']:.1f} ms/frame median "
          f"({timing['mean']:.1f} mean, first frame included, {summary['engine']}, {summary['decoder']} decoder) -> "
          f"{args.output}")
    if summary["tracking"]:
        tracking = summary["tracking"]
        print(f"  tracked at {tracking['fps']:g} frames/s: {tracking['tracks']} tracks, "
              f"{tracking['people_carried']} people carried through frames that missed them")
    print(fitness_line(summary["fitness"]))
    return 0
