"""Where a real frame's time goes in a bundle's runtime: per region, the network (by ONNX operator type, one
intra-op thread, onnxruntime's own profiler) and the decoding; the tracker per frame; the whole frame with the
regions in parallel and in turn.

    python experiments/2026-11-27-runtime-per-frame/runtime_profile.py BUNDLE --video V [--frames 1:400:10]
        [--threads 2] [--out experiments/2026-11-27-runtime-per-frame/results]

Writes ``runtime_profile.json`` and ``runtime_profile.md`` to ``--out``. Medians over the frames; the network
figures are onnxruntime's kernel times (no session overhead), so they add up to a little less than a run. Why:
issue 24 asks for 12 ms a PETS09 frame on 2 cores, and which part to cut depends on which thread is the critical
path when three regions share two cores.
"""

from __future__ import annotations

import argparse
import collections
import json
import os
import tempfile
import time
from pathlib import Path

import numpy as np
import onnxruntime as ort

from vc.cores import cpu_facts, usable_cores
from vc.deploy.frames import FrameRange, FrameSource
from vc.deploy.runtime import RegionRunner, Runtime
from vc.deploy.tracking import Tracker
from vc.io import write_json


def _median_ms(seconds: list[float]) -> float:
    return round(float(np.median(seconds)) * 1e3, 3)


def _region(runner: RegionRunner, frames: list[np.ndarray]) -> dict:
    """One region's network and decoding times (medians over the frames) and its ONNX operators' on one thread."""
    network, decoding = [], []
    for frame in frames:
        started = time.perf_counter()
        maps = runner.heatmaps(frame)
        middle = time.perf_counter()
        runner.people_in(maps)
        network.append(middle - started)
        decoding.append(time.perf_counter() - middle)
    x0, y0, width, height = runner.entry.crop_window
    crops = [np.ascontiguousarray(frame[y0:y0 + height, x0:x0 + width]) for frame in frames]
    return {"crop": [width, height], "input": list(runner.entry.input_size), "network_ms": _median_ms(network),
            "decode_ms": _median_ms(decoding), "operators_ms_one_thread": operator_times(runner.entry.model, crops)}


def operator_times(model: bytes, crops: list[np.ndarray]) -> dict[str, float]:
    """Milliseconds a run spends in each ONNX operator type (after onnxruntime's graph optimisations), one thread."""
    options = ort.SessionOptions()
    options.intra_op_num_threads = 1
    options.enable_profiling = True
    with tempfile.TemporaryDirectory() as folder:
        options.profile_file_prefix = os.path.join(folder, "profile")
        session = ort.InferenceSession(model, options, providers=["CPUExecutionProvider"])
        name = session.get_inputs()[0].name
        for crop in crops:
            session.run(None, {name: crop[None]})
        events = json.loads(Path(session.end_profiling()).read_text())
    totals: collections.Counter[str] = collections.Counter()
    for event in events:
        if event.get("cat") == "Node" and event["name"].endswith("_kernel_time"):
            totals[event["args"]["op_name"]] += event["dur"]
    return {op: round(microseconds / len(crops) / 1e3, 3) for op, microseconds in totals.most_common()}


def profile(bundle: Path, frames: list[np.ndarray], threads: int, fps: float) -> dict:
    result: dict = {"frames": len(frames), "threads": threads, "regions": {}}
    for parallel in (True, False):
        with Runtime(bundle, threads=threads, parallel_regions=parallel) as runtime:
            for frame in frames[:3]:
                runtime(frame)
            seconds, people = [], []
            for frame in frames:
                started = time.perf_counter()
                people.append(runtime(frame))
                seconds.append(time.perf_counter() - started)
            result["parallel_ms" if parallel else "in_turn_ms"] = _median_ms(seconds)
            if not parallel:  # the regions one by one, each with all the threads, as the frame just ran them
                for runner in runtime.runners:
                    result["regions"][runner.entry.name] = _region(runner, frames)
    tracker = Tracker()
    started = time.perf_counter()
    for index, (seen, frame) in enumerate(zip(people, frames, strict=True)):
        tracker.update(seen, index / fps, frame)
    result["tracker_ms"] = round((time.perf_counter() - started) / len(people) * 1e3, 3)
    return result


def report(result: dict, bundle: Path, video: Path) -> str:
    lines = [f"# Runtime profile: {bundle}", "",
             f"{result['frames']} real frames of {video.name}, {result['threads']} threads, {result['machine']}. "
             f"Whole frame: **{result['parallel_ms']} ms** with the regions in parallel, {result['in_turn_ms']} ms in "
             f"turn; the tracker {result['tracker_ms']} ms a frame.", "",
             "| region | crop -> input | network ms (in turn) | decode ms | largest operators, one thread (ms) |",
             "|---|---|---|---|---|"]
    for name, region in result["regions"].items():
        operators = ", ".join(f"{op} {ms}" for op, ms in list(region["operators_ms_one_thread"].items())[:4])
        lines.append(f"| {name} | {region['crop'][0]}x{region['crop'][1]} -> {region['input'][0]}x{region['input'][1]}"
                     f" | {region['network_ms']} | {region['decode_ms']} | {operators} |")
    return "\n".join(lines) + "\n"


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("bundle", type=Path)
    parser.add_argument("--video", type=Path, required=True, help="a video or folder of frames of the camera")
    parser.add_argument("--frames", type=FrameRange.parse, default=FrameRange(1, 400, 10))
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--fps", type=float, default=7.0, help="frame rate given to the tracker")
    parser.add_argument("--out", type=Path, default=Path(__file__).parent / "results")
    args = parser.parse_args(argv)
    frames = [frame.image for frame in FrameSource(args.video, args.frames)]
    result = profile(args.bundle, frames, args.threads, args.fps)
    result["machine"] = f"{cpu_facts()[0]}, {usable_cores()} usable cores"
    args.out.mkdir(parents=True, exist_ok=True)
    write_json(args.out / "runtime_profile.json", {"bundle": str(args.bundle), "video": str(args.video), **result})
    (args.out / "runtime_profile.md").write_text(report(result, args.bundle, args.video))
    print(report(result, args.bundle, args.video))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
