"""Low-capacity facing readers trained on renders, read on real people: a linear model (logistic regression, L-BFGS)
on a window of the crop in 2 x 2 cells, each crop standardised, in grey or colour, for the head alone or the whole
crop (common.KINDS). Does a reader that can only weigh where the crop is lighter or darker carry more to real people
than the classifier that learns the renders exactly? (frozen, issue 57 item 4)

    PYTHONPATH=src python experiments/2026-12-01-head-colours/probe/readers.py RENDER_CROPS.npz REAL.npz[,REAL.npz] \
        >> experiments/2026-12-01-head-colours/results/readers.jsonl
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np
import torch
from common import KINDS, cells, looks

from vc.model.facing import ranking


def fit(inputs: np.ndarray, targets: np.ndarray, l2: float, iterations: int = 200) -> torch.nn.Linear:
    features, labels = torch.from_numpy(inputs), torch.from_numpy(targets.astype(np.float32))
    linear = torch.nn.Linear(inputs.shape[1], 1)
    optimiser = torch.optim.LBFGS(linear.parameters(), max_iter=iterations)

    def loss() -> torch.Tensor:
        optimiser.zero_grad()
        value = (torch.nn.functional.binary_cross_entropy_with_logits(linear(features).squeeze(1), labels)
                 + l2 * linear.weight.square().sum())
        value.backward()
        return value

    optimiser.step(loss)
    return linear


def read(linear: torch.nn.Linear, crops: np.ndarray, kind: str) -> np.ndarray:
    with torch.no_grad():
        return linear(torch.from_numpy(cells(crops, kind))).squeeze(1).numpy()


def main() -> None:
    renders, reals = np.load(sys.argv[1]), [Path(p) for p in sys.argv[2].split(",")]
    rng = np.random.default_rng(0)
    chosen = rng.choice(len(renders["train_front"]), min(6000, len(renders["train_front"])), replace=False)
    drawn = looks(renders["train_crops"][chosen], rng)
    targets = np.tile(renders["train_front"][chosen], 3)
    for kind in KINDS:
        for l2 in (1e-3, 1e-1):
            linear = fit(cells(drawn, kind), targets, l2)
            held = read(linear, renders["held_out_crops"], kind)
            row = {"renders": Path(sys.argv[1]).stem, "kind": kind, "l2": l2,
                   "held_out": round(ranking(held, renders["held_out_front"]), 3)}
            for path in reals:
                real = np.load(path)
                logits = read(linear, real["crops"], kind)
                row[path.stem] = [round(ranking(logits, real["front"]), 3),
                                  round(float(((logits > 0) == real["front"]).mean()), 3)]
            print(json.dumps(row), flush=True)


if __name__ == "__main__":
    main()
