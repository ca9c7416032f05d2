"""Bundle runtime latency and memory per precision, as an appliance runs it: numpy + onnxruntime only.

    python benchmarks/runtime_latency.py --run RUN --scene SCENE [--precision fp32 fp16 int8] [--frames 30]
                                         [--threads 2] [--out benchmarks/results]

For each precision the finished vc-train RUN is exported to a temporary bundle (``vc.model.export``; int8
calibrated on the run's training renders) and measured in a fresh process, so that its peak resident memory is its
own: milliseconds per full frame (every region: crop, onnxruntime, decode, ownership, mapping; median over
``--frames`` frames composed of held-out renders on the scene's background, see :mod:`vc.evaluation.selftest`, after one
warm-up frame), sequentially with ``--threads`` intra-op threads and with the regions in parallel, and per region
(network and decoding alone). Writes ``runtime_latency.json``, ``runtime_latency.md`` and ``runtime_latency.png``
to ``--out``.
"""

from __future__ import annotations

import argparse
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


def _frames(run: Path, scene: Path, count: int) -> np.ndarray:
    from vc.evaluation.selftest import composite_frame
    from vc.io import read_image
    from vc.model.train import load_checkpoint
    from vc.render.dataset import open_region, read_manifest
    from vc.scenes.loader import load_scene

    checkpoint = load_checkpoint(sorted((run / "checkpoints").glob("*.pt"))[0])
    dataset = checkpoint.dataset
    regions = [open_region(dataset, name) for name in read_manifest(dataset)["regions"]]
    background = read_image(load_scene(scene).image_path)
    return np.stack([composite_frame(background, regions, index).image for index in range(count)])


def _write_report(results: dict, out: Path) -> None:
    from vc.io import write_json

    write_json(out / "runtime_latency.json", results)
    rows = results["precisions"]
    regions = list(next(iter(rows.values()))["regions"])
    lines = [f"Scene {results['scene']}, {results['frame_size'][0]}x{results['frame_size'][1]} frames, "
             f"{results['threads']} threads, median of {results['frames']} composed frames (numpy + onnxruntime "
             f"{results['onnxruntime']}).", "",
             "| precision | ms/frame (regions in turn) | ms/frame (regions in parallel) | "
             + " | ".join(f"{name} {'x'.join(map(str, rows[next(iter(rows))]['regions'][name]['input']))} net / "
                          f"+decode ms" for name in regions) + " | peak RSS MB |",
             "|---" * (4 + len(regions)) + "|"]
    for precision, row in rows.items():
        lines.append(f"| {precision} | {row['frame_ms']:.1f} | {row['frame_ms_parallel_regions']:.1f} | "
                     + " | ".join(f"{row['regions'][name]['network_ms']:.1f} / "
                                  f"{row['regions'][name]['network_and_decode_ms']:.1f}" for name in regions)
                     + f" | {row['peak_rss_mb']:.0f} |")
    (out / "runtime_latency.md").write_text("\n".join(lines) + "\n")
    figure, axes = plt.subplots(figsize=(6, 3.5))
    bottom = np.zeros(len(rows))
    for name in regions:
        values = np.array([row["regions"][name]["network_and_decode_ms"] for row in rows.values()])
        axes.bar(list(rows), values, bottom=bottom, label=name)
        bottom += values
    axes.plot(list(rows), [row["frame_ms"] for row in rows.values()], "ko", label="whole frame")
    axes.axhline(30, color="red", linestyle="--", linewidth=1, label="30 ms target")
    axes.set(ylabel="ms per frame", title=f"{results['scene']}: runtime per precision, {results['threads']} threads")
    axes.legend(fontsize=8)
    figure.tight_layout()
    figure.savefig(out / "runtime_latency.png", dpi=120)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--run", type=Path, help="a finished vc-train run")
    parser.add_argument("--scene", type=Path, help="its scene YAML (for the background)")
    parser.add_argument("--precision", nargs="+", choices=PRECISIONS, default=list(PRECISIONS))
    parser.add_argument("--frames", type=int, default=30)
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--out", type=Path, default=Path(__file__).parent / "results")
    parser.add_argument("--measure", nargs=2, type=Path, metavar=("BUNDLE", "FRAMES"), help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.measure:
        print(json.dumps(measure(*args.measure, args.threads)))
        return
    if not (args.run and args.scene):
        parser.error("--run and --scene are required")
    import onnxruntime

    from vc.model.export import bundle_files, write_bundle

    frames = _frames(args.run, args.scene, args.frames)
    results = {"run": str(args.run), "threads": args.threads, "frames": args.frames,
               "frame_size": [frames.shape[2], frames.shape[1]], "onnxruntime": onnxruntime.__version__,
               "precisions": {}}
    with tempfile.TemporaryDirectory(prefix="vc-latency-") as folder:
        np.save(Path(folder) / "frames.npy", frames)
        for precision in args.precision:
            manifest, files = bundle_files(args.run, precision, eval_samples=0)
            results["scene"] = manifest["scene"]
            write_bundle(manifest, files, Path(folder) / precision, as_zip=False)
            output = subprocess.run([sys.executable, __file__, "--threads", str(args.threads), "--measure",
                                     str(Path(folder) / precision), str(Path(folder) / "frames.npy")],
                                    capture_output=True, text=True, check=True).stdout
            results["precisions"][precision] = json.loads(output.strip().splitlines()[-1])
            row = results["precisions"][precision]
            print(f"{precision}: {row['frame_ms']:.1f} ms/frame ({row['frame_ms_parallel_regions']:.1f} with regions "
                  f"in parallel), peak {row['peak_rss_mb']:.0f} MB", flush=True)
    args.out.mkdir(parents=True, exist_ok=True)
    _write_report(results, args.out)


if __name__ == "__main__":
    main()
