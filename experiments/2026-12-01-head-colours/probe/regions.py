"""Which rows of the crop carry a facing cue that carries over from renders to real people? The shipped classifier's
recipe (vc.model.facing: FacingNet, eight epochs, the camera's look, mirrors) trained on one band of rows of a
compile's render crops, read on real people (frozen, issue 57 item 4).

    PYTHONPATH=src python experiments/2026-12-01-head-colours/probe/regions.py RENDER_CROPS.npz REAL.npz[,REAL.npz] \
        SEED full,head,headonly,nohead,torso,legs >> experiments/2026-12-01-head-colours/results/regions.jsonl

RENDER_CROPS.npz: experiments/2026-11-30-facing-camera-look/harness.py's ``renders`` output; REAL.npz: realset.py's.
"""

from __future__ import annotations

import json
import sys
import time
from pathlib import Path

import numpy as np
import torch
from torch import nn

from vc.model import facing as shipped
from vc.model.facing import ranking

ROWS = {"full": (0, 64), "head": (0, 20), "headonly": (0, 14), "nohead": (14, 64), "torso": (10, 40), "legs": (36, 64)}


def _logits(net: nn.Module, crops: np.ndarray) -> np.ndarray:
    net.eval()
    with torch.no_grad():
        return torch.cat([net(shipped._batch(crops[start:start + 512])) for start in range(0, len(crops), 512)]).numpy()


def train(band: str, renders: Path, reals: list[Path], seed: int, epochs: int = shipped.EPOCHS) -> dict:
    r0, r1 = ROWS[band]
    data = np.load(renders)
    crops, front = data["train_crops"], data["train_front"]
    torch.manual_seed(seed)
    rng = np.random.default_rng(seed)
    net = shipped.FacingNet()
    steps = len(front) // shipped.BATCH
    optimiser = torch.optim.AdamW(net.parameters(), shipped.LEARNING_RATE / 1.5, weight_decay=1e-4)
    schedule = torch.optim.lr_scheduler.OneCycleLR(optimiser, shipped.LEARNING_RATE, total_steps=epochs * steps)
    labels = torch.from_numpy(front.astype(np.float32))
    start = time.perf_counter()
    for _ in range(epochs):
        net.train()
        order = rng.permutation(len(front))
        for step in range(steps):
            chosen = order[step * shipped.BATCH:(step + 1) * shipped.BATCH]
            looks = np.stack([shipped.camera_look(crop, rng) for crop in crops[chosen]])
            mirrored = rng.random(len(chosen)) < 0.5
            looks[mirrored] = looks[mirrored, :, ::-1]
            loss = nn.functional.binary_cross_entropy_with_logits(
                net(shipped._batch(np.ascontiguousarray(looks[:, r0:r1]))), labels[chosen])
            optimiser.zero_grad()
            loss.backward()
            optimiser.step()
            schedule.step()
    held = _logits(net, np.ascontiguousarray(data["held_out_crops"][:, r0:r1]))
    row = {"rows": band, "renders": renders.stem, "seed": seed, "seconds": round(time.perf_counter() - start),
           "held_out": [round(ranking(held, data["held_out_front"]), 3),
                        round(float(((held > 0) == data["held_out_front"]).mean()), 3)]}
    for path in reals:
        real = np.load(path)
        logits = _logits(net, np.ascontiguousarray(real["crops"][:, r0:r1]))
        row[path.stem] = [round(ranking(logits, real["front"]), 3),
                          round(float(((logits > 0) == real["front"]).mean()), 3)]
    return row


def main() -> None:
    renders, reals, seed = Path(sys.argv[1]), [Path(p) for p in sys.argv[2].split(",")], int(sys.argv[3])
    for band in sys.argv[4].split(","):
        print(json.dumps(train(band, renders, reals, seed)), flush=True)


if __name__ == "__main__":
    main()
