"""What a head network beside today's r0 costs a frame with the runtime as shipped (C decoder, regions in parallel,
one thread each), on TUD-Stadtmitte's frames 1-90 (frozen experiment, issue 57 item 2).

    PYTHONPATH=../.. python cost.py CONTROL_BUNDLE HEAD_BUNDLE [HEAD_BUNDLE ...] [-o results/cost.txt]

0036 timed the union with the numpy decoder (``../2026-12-01-head-beside-centre/cost.py``), which its experiment
patched to decode the head maps; the runtime decodes with the C decoder. Here r0's runner also runs the head
network's graph on its crop and decodes its maps with the C decoder at r0's settings, then adds the head network's
people that overlap none of r0's at IoU 0.5. The head maps are decoded as a centre map would be (the C decoder does
not read offsets in cells): the same work, not the same people, so the time is the union's and nothing else is read
from it. Each arm runs the 90 frames twice and the second pass is timed (ms a frame, ``Runtime.run`` end to end);
the arms run in turn, ``--rounds`` times, since a shared machine's speed drifts between minutes (one round each read
1.42x and 1.21x for the same union). Ratios are of the median rounds, all in one run.
"""

from __future__ import annotations

import argparse
import platform
import subprocess
import time
from pathlib import Path

import numpy as np

from vc.deploy.boxes import box_iou
from vc.deploy.frames import FrameRange, FrameSource
from vc.deploy.runtime import Runtime

TUD_FRAMES = Path(__file__).resolve().parents[3] / "shared" / "data" / "tud_stadtmitte" / "frames"
ADDED_BELOW_IOU = 0.5


def frame_ms(running: Runtime, frames: list[np.ndarray]) -> np.ndarray:
    """ms of each of ``frames`` through ``running``, timed on a second pass (the first warms the graphs up)."""
    for image in frames:
        running.run(image)
    times = np.empty(len(frames))
    for index, image in enumerate(frames):
        start = time.perf_counter()
        running.run(image)
        times[index] = (time.perf_counter() - start) * 1000
    return times


def with_head(running: Runtime, head: Runtime) -> None:
    """``running``'s r0 also decodes ``head``'s r0 network and adds its people that overlap none of its own."""
    today, beside = running.runners[0], head.runners[0]
    own_people = today.people

    def people(frame: np.ndarray) -> list:
        mine = own_people(frame)
        theirs = beside.people_in(beside.heatmaps(frame))
        if not mine:
            return mine + theirs
        overlaps = box_iou(np.array([person.box for person in theirs]).reshape(-1, 4),
                           np.array([person.box for person in mine]))
        return mine + [person for person, row in zip(theirs, overlaps, strict=True) if row.max() < ADDED_BELOW_IOU]

    today.people = people


def machine() -> str:
    model = [line for line in subprocess.run(["lscpu"], capture_output=True, text=True).stdout.splitlines()
             if line.startswith("Model name")]
    return (model[0].split(":", 1)[1].strip() if model else platform.processor()) + f", {platform.machine()}"


def arm_ms(control: Path, head_bundle: Path | None, frames: list[np.ndarray]) -> np.ndarray:
    """ms of each frame through today's bundle, with ``head_bundle``'s network beside r0 where given."""
    with Runtime(control, threads=2) as running:
        if head_bundle is None:
            return frame_ms(running, frames)
        with Runtime(head_bundle, threads=1) as head:
            with_head(running, head)
            return frame_ms(running, frames)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("control", type=Path)
    parser.add_argument("heads", type=Path, nargs="+")
    parser.add_argument("--rounds", type=int, default=5, help="rounds of every arm in turn (default 5)")
    parser.add_argument("-o", "--out", type=Path)
    args = parser.parse_args()
    frames = [frame.image for frame in FrameSource(TUD_FRAMES, FrameRange.parse("1:90"))]
    arms: dict[str, Path | None] = {"today's bundle": None, **{f"+ {head.name} beside r0": head for head in args.heads}}
    medians: dict[str, list[float]] = {name: [] for name in arms}
    for _ in range(args.rounds):
        for name, head_bundle in arms.items():
            medians[name].append(float(np.median(arm_ms(args.control, head_bundle, frames))))
    today = np.median(medians["today's bundle"])
    lines = [f"machine: {machine()}; runtime as shipped (C decoder), 2 threads, regions in parallel",
             f"ms a frame, TUD-Stadtmitte 1-90: each round's median frame, {args.rounds} rounds of the arms in turn; "
             f"the median round, its ratio to today's, and every round"]
    for name, rounds in medians.items():
        middle = np.median(rounds)
        lines.append(f"{name}: {middle:.2f} ({middle / today:.2f}x); rounds " + " ".join(f"{ms:.2f}" for ms in rounds))
    print("\n".join(lines))
    if args.out:
        args.out.parent.mkdir(parents=True, exist_ok=True)
        args.out.write_text("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
