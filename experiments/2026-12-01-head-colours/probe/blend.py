"""The bundle's classifier (its own front logit, from realset.py) against the head reader vc-train now trains
(vc.model.facing.train_head_colours, on the same compile's render crops with its seed), and the head's logit plus
the classifier's at a weight, on real people: the share read the reference's way and the AUC (frozen, issue 57).

    PYTHONPATH=src python experiments/2026-12-01-head-colours/probe/blend.py RENDER_CROPS.npz SEED REAL.npz[,...] \
        >> experiments/2026-12-01-head-colours/results/blend.jsonl
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np
import torch

from vc.model.facing import FacingCrops, _batch, ranking, train_head_colours

WEIGHTS = (0.0, 0.05, 0.1, 0.2)


def main() -> None:
    renders, seed = np.load(sys.argv[1]), int(sys.argv[2])
    head = train_head_colours(FacingCrops(renders["train_crops"], renders["train_front"]),
                              FacingCrops(renders["held_out_crops"], renders["held_out_front"]), seed)
    for path in (Path(p) for p in sys.argv[3].split(",")):
        real = np.load(path)
        with torch.no_grad():
            heads = head.net(_batch(real["crops"])).numpy()
        classifier, front = real["logits"], real["front"]
        row = {"renders": Path(sys.argv[1]).stem, "seed": seed, "real": path.stem, "people": len(front),
               "front_share": round(float(front.mean()), 3), "head_held_out": head.to_dict(),
               "classifier": [round(ranking(classifier, front), 3),
                              round(float(((classifier > 0) == front).mean()), 3)]}
        for weight in WEIGHTS:
            logits = heads + weight * classifier
            row[f"head + {weight} classifier"] = [round(ranking(logits, front), 3),
                                                  round(float(((logits > 0) == front).mean()), 3)]
        print(json.dumps(row), flush=True)


if __name__ == "__main__":
    main()
