"""Decoding time per frame, the C decoder against numpy's, and whether they report the same people, on real frames.

    python -m benchmarks.decode_speed BUNDLE --video V [--frames 1:400] [--threads 2] [--repeats 3]
                                      [--out benchmarks/results/decode_speed]

Each frame's heat maps (every region, onnxruntime) are computed once and decoded by both decoders in turn,
``--repeats`` times (numpy, C, numpy, C, ...): the ratio of their times holds on a shared machine whose speed drifts.
Per frame, the people each region's decoders report are compared: count, the largest box, centre and keypoint
differences (px), score differences, masks. Then the whole runtime per frame (crop, networks, decoding, ownership,
fitness), with each decoder, frame by frame in turn. Writes ``decode_speed.json``, ``decode_speed.md`` and
``decode_speed.png`` to ``--out``; the report names the CPU.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from benchmarks import display_path, results_folder  # noqa: E402


def _timed(function, *arguments) -> tuple[float, object]:
    start = time.perf_counter()
    result = function(*arguments)
    return time.perf_counter() - start, result


def _differences(reference: list, ours: list) -> dict:
    """How far one region's people from the C decoder lie from numpy's (same order: the decoders' own)."""
    if len(reference) != len(ours):
        return {"count_equal": False}
    largest = {"box_px": 0.0, "centre_px": 0.0, "keypoint_px": 0.0, "score": 0.0}
    masks_equal = True
    for a, b in zip(reference, ours, strict=True):
        largest["box_px"] = max(largest["box_px"], float(np.abs(a.box - b.box).max()))
        largest["centre_px"] = max(largest["centre_px"], float(np.abs(a.centre - b.centre).max()))
        largest["keypoint_px"] = max(largest["keypoint_px"],
                                     float(np.abs(a.keypoints[:, :2] - b.keypoints[:, :2]).max()))
        largest["score"] = max(largest["score"], abs(a.score - b.score))
        masks_equal &= bool((a.mask_cells == b.mask_cells).all())
    return {"count_equal": True, "masks_equal": masks_equal, **largest}


def measure(bundle: Path, video: Path, frames: str, threads: int, repeats: int) -> dict:
    from vc.cores import cpu_facts
    from vc.deploy import native
    from vc.deploy.decode import decode
    from vc.deploy.frames import FrameRange, FrameSource
    from vc.deploy.runtime import Runtime
    from vc.deploy.tracking import TrackingConfig

    # as vc-run runs it, tracking: the weak people a tracker continues tracks with are decoded too
    weak = TrackingConfig().weak_people_above
    runtimes = {name: Runtime(bundle, threads=threads, parallel_regions=False, weak_people_above=weak, decoder=name)
                for name in ("numpy", "c")}
    decoders = {"numpy": decode, "c": native.decode}
    decode_s = {name: [] for name in decoders}
    runtime_s = {name: [] for name in runtimes}
    people, unequal_frames, worst = 0, 0, {"box_px": 0.0, "centre_px": 0.0, "keypoint_px": 0.0, "score": 0.0}
    masks_equal = True
    count = 0
    for frame in FrameSource(video, FrameRange.parse(frames)):
        totals = {name: 0.0 for name in decoders}
        frame_equal = True
        for runner in runtimes["numpy"].runners:
            heatmaps, entry = runner.heatmaps(frame.image), runner.entry
            found = {}
            for _ in range(repeats):
                for name, function in decoders.items():
                    seconds, found[name] = _timed(function, heatmaps, entry.decode, entry.expected_height_px,
                                                  runner.weak_people_above)
                    totals[name] += seconds / repeats
            difference = _differences(found["numpy"], found["c"])
            people += len(found["numpy"])
            frame_equal &= difference["count_equal"]
            if difference["count_equal"]:
                masks_equal &= difference["masks_equal"]
                worst = {key: max(value, difference[key]) for key, value in worst.items()}
        unequal_frames += not frame_equal
        for name in decoders:
            decode_s[name].append(totals[name])
        for name, runtime in runtimes.items():
            runtime_s[name].append(_timed(runtime, frame.image)[0])
        count += 1
    median_ms = {name: 1e3 * float(np.median(values[1:] or values)) for name, values in decode_s.items()}
    runtime_ms = {name: 1e3 * float(np.median(values[1:] or values)) for name, values in runtime_s.items()}
    return {"bundle": display_path(bundle), "video": display_path(video), "frames": frames, "frames_measured": count,
            "threads": threads, "repeats": repeats, "cpu": cpu_facts()[0],
            "people_decoded": people, "frames_with_another_count": unequal_frames, "masks_equal": masks_equal,
            "largest_difference": worst,
            "decode_ms_per_frame_median": median_ms,
            "decode_ratio_c_to_numpy": median_ms["c"] / median_ms["numpy"],
            "runtime_ms_per_frame_median": runtime_ms,
            "runtime_ratio_c_to_numpy": runtime_ms["c"] / runtime_ms["numpy"]}


def write_report(results: dict, out: Path) -> None:
    from vc.io import write_json

    out.mkdir(parents=True, exist_ok=True)
    write_json(out / "decode_speed.json", results)
    decode_ms, runtime_ms, worst = (results["decode_ms_per_frame_median"], results["runtime_ms_per_frame_median"],
                                    results["largest_difference"])
    lines = [f"Bundle `{results['bundle']}`, frames {results['frames']} of `{results['video']}` "
             f"({results['frames_measured']} frames, {results['people_decoded']} people decoded per decoder), "
             f"{results['cpu']}, {results['threads']} threads; medians per frame, the decoders timed in turn "
             f"{results['repeats']} times on each frame's heat maps.", "",
             "| | numpy | C | C / numpy |", "|---|---|---|---|",
             f"| decoding, ms per frame | {decode_ms['numpy']:.2f} | {decode_ms['c']:.2f} | "
             f"{results['decode_ratio_c_to_numpy']:.3f} |",
             f"| whole runtime, ms per frame | {runtime_ms['numpy']:.1f} | {runtime_ms['c']:.1f} | "
             f"{results['runtime_ratio_c_to_numpy']:.3f} |", "",
             f"Same people: {results['frames_measured'] - results['frames_with_another_count']} of "
             f"{results['frames_measured']} frames with equal counts; largest differences: box "
             f"{worst['box_px']:.2g} px, centre {worst['centre_px']:.2g} px, keypoint {worst['keypoint_px']:.2g} px, "
             f"score {worst['score']:.2g}; masks {'equal' if results['masks_equal'] else 'NOT equal'}."]
    (out / "decode_speed.md").write_text("\n".join(lines) + "\n")
    figure, axis = plt.subplots(figsize=(6, 3))
    labels = ["decoding", "whole runtime"]
    for offset, name in ((-0.2, "numpy"), (0.2, "c")):
        axis.bar(np.arange(2) + offset, [decode_ms[name], runtime_ms[name]], width=0.4,
                 label="numpy" if name == "numpy" else "C")
    axis.set_xticks(range(2), labels)
    axis.set_ylabel("ms per frame (median)")
    axis.set_title(f"{results['bundle']}: C / numpy = {results['decode_ratio_c_to_numpy']:.2f} (decoding)",
                   fontsize=9)
    axis.legend()
    figure.tight_layout()
    figure.savefig(out / "decode_speed.png", dpi=120)
    plt.close(figure)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("bundle", type=Path)
    parser.add_argument("--video", type=Path, required=True, help="the camera's video or folder of frames")
    parser.add_argument("--frames", default="1:400", help="first:last[:step] (default 1:400)")
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--out", type=Path, default=results_folder("decode_speed"))
    args = parser.parse_args(argv)
    results = measure(args.bundle, args.video, args.frames, args.threads, args.repeats)
    write_report(results, args.out)
    print((args.out / "decode_speed.md").read_text())
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
