"""Where a CPU compile cuts its training windows: in the training process (``--workers 0``) or in a loader process
(``--workers 1``), timed on the same renders and steps, in turn, in one run.

    python experiments/2026-11-26-compile-time/loader_placement.py RENDERS [--region r1] [--steps 240] [--rounds 2]
        [--workers 0 1] --out DIR

Each round trains the region once per placement (``vc-train RENDERS -o DIR/run-wN-k --region R --steps S --workers
N``) and reads the run's own figures (training seconds and images per second from ``metrics.json``); the wall time
includes start-up and the held-out evaluation. Items are pure functions of (seed, draw), so every placement trains
the same weights; that is checked tensor for tensor. Writes ``DIR/loader_placement.json`` and one line per run.
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import time
from pathlib import Path

import torch

from vc.cores import cpu_facts, usable_cores
from vc.errors import InputError, StageError
from vc.io import write_json


def train_once(renders: Path, run: Path, region: str, steps: int, workers: int) -> dict:
    """One ``vc-train`` run in a fresh process (as a compile runs it); its own figures and the wall time."""
    started = time.perf_counter()
    done = subprocess.run([str(Path(sys.executable).with_name("vc-train")), str(renders), "-o", str(run), "--region",
                           region, "--steps", str(steps), "--workers", str(workers), "--quiet"],
                          stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    if done.returncode:  # vc-train said why in one line; bad input (status 2) stays bad input here
        reason = done.stderr.strip().splitlines()[-1].removeprefix("error: ") if done.stderr.strip() else "failed"
        raise (InputError(None, "", reason) if done.returncode == 2 else StageError(f"vc-train: {reason}"))
    wall = time.perf_counter() - started
    figures = json.loads((run / "metrics.json").read_text())["regions"][region]
    return {"workers": workers, "wall_s": round(wall, 2), "train_s": figures["train_seconds"],
            "img_s": figures["train_images_per_second"], "final_loss": figures["final_loss"]}


def same_weights(first: Path, second: Path, region: str) -> bool:
    a, b = (torch.load(run / "checkpoints" / f"{region}.pt", weights_only=False)["model"] for run in (first, second))
    return a.keys() == b.keys() and all(torch.equal(a[name], b[name]) for name in a)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("renders", type=Path)
    parser.add_argument("--region", default="r1")
    parser.add_argument("--steps", type=int, default=240)
    parser.add_argument("--rounds", type=int, default=2)
    parser.add_argument("--workers", type=int, nargs="+", default=[0, 1])
    parser.add_argument("--out", type=Path, required=True)
    args = parser.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    runs, folders = [], {}
    for round_index in range(args.rounds):
        for workers in args.workers:
            folder = args.out / f"run-w{workers}-{round_index}"
            try:
                result = train_once(args.renders, folder, args.region, args.steps, workers) | {"round": round_index}
            except InputError as error:
                parser.error(str(error))
            except StageError as error:
                print(f"error: {error}", file=sys.stderr)
                return 1
            folders.setdefault(workers, folder)
            runs.append(result)
            print(f"round {round_index} workers {workers}: train {result['train_s']:.1f} s, "
                  f"{result['img_s']:.1f} img/s, wall {result['wall_s']:.1f} s")
    reference = folders[args.workers[0]]
    identical = all(same_weights(reference, folder, args.region) for folder in folders.values())
    summary = {workers: round(sum(r["train_s"] for r in runs if r["workers"] == workers)
                              / sum(1 for r in runs if r["workers"] == workers), 2) for workers in args.workers}
    write_json(args.out / "loader_placement.json", {
        "renders": str(args.renders), "region": args.region, "steps": args.steps,
        "machine": f"{cpu_facts()[0]}, {usable_cores()} usable cores",
        "runs": runs, "mean_train_s": {str(k): v for k, v in summary.items()}, "weights_identical": identical})
    print(json.dumps({"mean_train_s": summary, "weights_identical": identical}))
    return 0 if identical else 1


if __name__ == "__main__":
    raise SystemExit(main())
