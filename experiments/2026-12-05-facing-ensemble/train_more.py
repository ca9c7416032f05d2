"""More facing models for one compile: trained on its own renders as a compile trains its one
(:func:`vc.stages.train.train_facing_model`), with other training seeds (frozen experiment, issue 57 item 4).

    PYTHONPATH=../../src python train_more.py RENDERS OUT SEED...

Writes ``OUT/seedSEED/facing.onnx`` and ``facing.json`` per seed; a finished one is kept.
"""

from __future__ import annotations

import sys
from pathlib import Path

from vc.stages.train import train_facing_model

if __name__ == "__main__":
    renders, out = Path(sys.argv[1]), Path(sys.argv[2])
    for seed in map(int, sys.argv[3:]):
        run = out / f"seed{seed}"
        run.mkdir(parents=True, exist_ok=True)
        measured = train_facing_model(renders, run, seed, show_progress=False)
        print(f"{renders} seed {seed}: held-out accuracy {measured['held_out_accuracy']}", flush=True)
