"""Bundle runtime latency and memory per precision, as an appliance runs it: numpy + onnxruntime only.

    python -m benchmarks.runtime_latency --run RUN --scene SCENE [--baseline-run RUN] [--precision fp32 fp16 int8]
                                         [--frames 30] [--video V [--video-frames 1:400:5]] [--threads 2]
                                         [--out benchmarks/results/runtime_latency]

For each precision the finished vc-train RUN is exported to a temporary bundle (``vc.model.export``; int8
calibrated on the run's training renders) and measured in a fresh process, so that its peak resident memory is its
own: milliseconds per full frame (every region: crop, onnxruntime, decode, ownership, mapping; median over
``--frames`` frames composed of held-out renders on the scene's background, see :mod:`vc.evaluation.selftest`, after one
warm-up frame), sequentially with ``--threads`` intra-op threads and with the regions in parallel, and per region
(network and decoding alone). Writes ``runtime_latency.json``, ``runtime_latency.md`` and ``runtime_latency.png``
to ``--out``; the report names the runs by their folders' names (or their paths inside the repository).

``--video``: time the first ``--frames`` real frames of the camera's video (``--video-frames`` selects them)
instead of composed ones, which hold more people than a real frame and so weigh decoding more.

``--baseline-run``: today's compile of the same scene, measured in the same invocation on the same frames, each
precision's two bundles in turn twice (baseline, run, baseline, run), so that the ratio of the two holds on a
shared machine whose speed drifts; the report gives the run's times as ratios to the baseline's.
"""

from __future__ import annotations

import argparse
import itertools
import json
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from benchmarks import REPOSITORY, display_path, results_folder  # noqa: E402

PRECISIONS = ("fp32", "fp16", "int8")


def _median_ms(run, repetitions: int) -> float:
    run()
    times = []
    for _ in range(repetitions):
        start = time.perf_counter()
        run()
        times.append((time.perf_counter() - start) * 1e3)
    return float(np.median(times))


def measure(bundle: Path, frames_path: Path, threads: int) -> dict:
    """In this process (started fresh by :func:`main`): the bundle's timings on the saved frames."""
    from vc.deploy.runtime import Runtime

    frames = np.load(frames_path)
    before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    sequential = Runtime(bundle, threads=threads, parallel_regions=False)
    loaded = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    index = iter(range(10**9))
    frame_ms = _median_ms(lambda: sequential(frames[next(index) % len(frames)]), len(frames))
    per_region = {}
    for runner in sequential.runners:
        per_region[runner.entry.name] = {
            "input": list(runner.entry.input_size), "precision": runner.entry.precision,
            "network_ms": _median_ms(lambda r=runner: r.heatmaps(frames[0]), len(frames)),
            "network_and_decode_ms": _median_ms(lambda r=runner: r.people(frames[0]), len(frames))}
    parallel = Runtime(bundle, threads=threads, parallel_regions=True)
    index = iter(range(10**9))
    parallel_ms = _median_ms(lambda: parallel(frames[next(index) % len(frames)]), len(frames))
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    return {"frame_ms": frame_ms, "frame_ms_parallel_regions": parallel_ms, "regions": per_region,
            "peak_rss_mb": peak / 1024, "model_load_rss_mb": (loaded - before) / 1024}


def _video_frames(video: Path, selection: str, count: int) -> np.ndarray:
    from vc.deploy.frames import FrameRange, FrameSource

    return np.stack([frame.image for frame in itertools.islice(FrameSource(video, FrameRange.parse(selection)),
                                                                 count)])


def _frames(run: Path, scene: Path, count: int) -> np.ndarray:
    from vc.evaluation.selftest import composite_frame
    from vc.io import read_image
    from vc.model.trainer import load_checkpoint
    from vc.render.dataset import open_region, read_manifest
    from vc.scenes.loader import load_scene

    checkpoint = load_checkpoint(sorted((run / "checkpoints").glob("*.pt"))[0])
    dataset = checkpoint.dataset
    regions = [open_region(dataset, name) for name in read_manifest(dataset)["regions"]]
    background = read_image(load_scene(scene).image_path)
    return np.stack([composite_frame(background, regions, index).image for index in range(count)])


def _measure_in_fresh_process(bundle: Path, frames_path: Path, threads: int) -> dict:
    """:func:`measure` in a new interpreter, so that the peak resident memory is this bundle's own."""
    command = [sys.executable, "-m", "benchmarks.runtime_latency", "--threads", str(threads), "--measure", str(bundle),
               str(frames_path)]
    output = subprocess.run(command, capture_output=True, text=True, check=True, cwd=REPOSITORY).stdout
    return json.loads(output.strip().splitlines()[-1])


def _interleaved(bundles: dict[str, Path], frames_path: Path, threads: int, repeats: int) -> dict[str, list[dict]]:
    """Each bundle measured ``repeats`` times, in turn (baseline, run, baseline, run): a drift of the machine's
    speed during the measurement falls on both alike."""
    rounds: dict[str, list[dict]] = {role: [] for role in bundles}
    for _ in range(repeats):
        for role, bundle in bundles.items():
            rounds[role].append(_measure_in_fresh_process(bundle, frames_path, threads))
    return rounds


def _mean_of_rounds(measured: list[dict]) -> dict:
    """One bundle's rounds as one row: times averaged, memory the largest."""
    first = measured[0]
    return {"frame_ms": float(np.mean([m["frame_ms"] for m in measured])),
            "frame_ms_parallel_regions": float(np.mean([m["frame_ms_parallel_regions"] for m in measured])),
            "regions": {name: {**region, **{key: float(np.mean([m["regions"][name][key] for m in measured]))
                                            for key in ("network_ms", "network_and_decode_ms")}}
                        for name, region in first["regions"].items()},
            "peak_rss_mb": max(m["peak_rss_mb"] for m in measured),
            "model_load_rss_mb": max(m["model_load_rss_mb"] for m in measured), "rounds": len(measured)}


def _write_report(results: dict, out: Path) -> None:
    from vc.io import write_json

    write_json(out / "runtime_latency.json", results)
    rows = results["precisions"]
    regions = list(next(iter(rows.values()))["regions"])
    baseline = results.get("baseline", {})
    lines = [f"Scene {results['scene']}, {results['frame_size'][0]}x{results['frame_size'][1]} frames, "
             f"{results['threads']} threads, median of {results['frames']} "
             f"{results.get('frames_from', 'composed frames')} (numpy + onnxruntime {results['onnxruntime']})."
             + (f" Run `{results['run']}` against the baseline `{results['baseline_run']}`, measured in turn twice "
                f"in this invocation." if baseline else ""), "",
             "| bundle | ms/frame (regions in turn) | ms/frame (regions in parallel) | "
             + " | ".join(f"{name} net / +decode ms" for name in regions) + " | inputs | peak RSS MB |",
             "|---" * (5 + len(regions)) + "|"]
    labelled = [(f"{precision} baseline", baseline[precision]) for precision in rows if precision in baseline]
    labelled = sorted(labelled + list(rows.items()), key=lambda item: list(rows).index(item[0].split()[0]))
    for label, row in labelled:
        lines.append(f"| {label} | {row['frame_ms']:.1f} | {row['frame_ms_parallel_regions']:.1f} | "
                     + " | ".join(f"{row['regions'][name]['network_ms']:.1f} / "
                                  f"{row['regions'][name]['network_and_decode_ms']:.1f}" for name in regions)
                     + " | " + ", ".join("x".join(map(str, row["regions"][name]["input"])) for name in regions)
                     + f" | {row['peak_rss_mb']:.0f} |")
    for precision, ratio in results.get("vs_baseline", {}).items():
        lines.append(f"\n{precision}: {ratio['frame_ms']:.2f}x the baseline's time with regions in turn, "
                     f"{ratio['frame_ms_parallel_regions']:.2f}x with regions in parallel.")
    (out / "runtime_latency.md").write_text("\n".join(lines) + "\n")
    figure, axes = plt.subplots(figsize=(8, 3.5))
    labels = [label for label, _ in labelled]
    bottom = np.zeros(len(labelled))
    for name in regions:
        values = np.array([row["regions"][name]["network_and_decode_ms"] for _, row in labelled])
        axes.bar(labels, values, bottom=bottom, label=name)
        bottom += values
    axes.plot(labels, [row["frame_ms"] for _, row in labelled], "ko", label="whole frame, regions in turn")
    axes.plot(labels, [row["frame_ms_parallel_regions"] for _, row in labelled], "k^",
              label="whole frame, regions in parallel")
    for target, style in ((30, "--"), (12, ":")):
        axes.axhline(target, color="red", linestyle=style, linewidth=1, label=f"{target} ms target")
    axes.tick_params(axis="x", labelsize=8)
    axes.set(ylabel="ms per frame", title=f"{results['scene']}: runtime per precision, {results['threads']} threads")
    axes.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    figure.tight_layout()
    figure.savefig(out / "runtime_latency.png", dpi=120)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--run", type=Path, help="a finished vc-train run")
    parser.add_argument("--scene", type=Path, help="its scene YAML (for the background)")
    parser.add_argument("--baseline-run", type=Path,
                        help="today's vc-train run of the same scene: the run's times are reported as ratios to its")
    parser.add_argument("--precision", nargs="+", choices=PRECISIONS, default=list(PRECISIONS))
    parser.add_argument("--frames", type=int, default=30)
    parser.add_argument("--video", type=Path, help="time real frames of this video (or folder of images)")
    parser.add_argument("--video-frames", default="1:400:5", help="which frames of --video (first:last:step)")
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--out", type=Path, default=results_folder("runtime_latency"))
    parser.add_argument("--measure", nargs=2, type=Path, metavar=("BUNDLE", "FRAMES"), help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.measure:
        print(json.dumps(measure(*args.measure, args.threads)))
        return
    if not (args.run and args.scene):
        parser.error("--run and --scene are required")
    import onnxruntime

    from vc.deploy.frames import FrameRange
    from vc.model.export import bundle_files, write_bundle

    if args.video is not None and not args.video.exists():
        parser.error(f"--video {args.video}: no such file or folder")
    try:
        FrameRange.parse(args.video_frames)
    except argparse.ArgumentTypeError as error:
        parser.error(f"--video-frames: {error}")
    frames = (_frames(args.run, args.scene, args.frames) if args.video is None
              else _video_frames(args.video, args.video_frames, args.frames))
    results = {"run": display_path(args.run), "threads": args.threads, "frames": len(frames),
               "frames_from": "composed frames" if args.video is None
               else f"real frames ({args.video.name}, {args.video_frames})",
               "frame_size": [frames.shape[2], frames.shape[1]], "onnxruntime": onnxruntime.__version__,
               "precisions": {}}
    runs = {"run": args.run} if args.baseline_run is None else {"baseline": args.baseline_run, "run": args.run}
    with tempfile.TemporaryDirectory(prefix="vc-latency-") as folder:
        frames_path = Path(folder) / "frames.npy"
        np.save(frames_path, frames)
        for precision in args.precision:
            bundles = {}
            for role, run in runs.items():
                manifest, files = bundle_files(run, precision, eval_samples=0)
                results["scene"] = manifest["scene"]
                bundles[role] = Path(folder) / f"{role}-{precision}"
                write_bundle(manifest, files, bundles[role], as_zip=False)
            rounds = _interleaved(bundles, frames_path, args.threads, repeats=2 if len(bundles) > 1 else 1)
            for role, measured in rounds.items():
                row = _mean_of_rounds(measured)
                (results["precisions"] if role == "run" else results.setdefault("baseline", {}))[precision] = row
                print(f"{precision} {role}: {row['frame_ms']:.1f} ms/frame ({row['frame_ms_parallel_regions']:.1f} "
                      f"with regions in parallel), peak {row['peak_rss_mb']:.0f} MB", flush=True)
    if args.baseline_run is not None:
        results["baseline_run"] = display_path(args.baseline_run)
        results["vs_baseline"] = {
            precision: {key: row[key] / results["baseline"][precision][key]
                        for key in ("frame_ms", "frame_ms_parallel_regions")}
            for precision, row in results["precisions"].items()}
    args.out.mkdir(parents=True, exist_ok=True)
    _write_report(results, args.out)


if __name__ == "__main__":
    main()
