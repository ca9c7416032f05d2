"""ROC AUC of each feature (and of simple combinations) for telling the added people who are someone.

    python auc.py results/seed0_choosing.jsonl [...]
"""
import json
import sys

import numpy as np


def roc_auc_score(label: np.ndarray, values: np.ndarray) -> float:
    """The chance a random someone scores above a random nobody (ties half): the Mann-Whitney statistic."""
    positive, negative = values[label], values[~label]
    above = (positive[:, None] > negative[None, :]).sum() + 0.5 * (positive[:, None] == negative[None, :]).sum()
    return float(above / (len(positive) * len(negative)))

for path in sys.argv[1:]:
    rows = [json.loads(line) for line in open(path)]
    label = np.array([r["someone"] for r in rows])
    features = {name: np.array([r[name] for r in rows]) for name in ("strength", "head", "shoulders", "sideways")}
    features["head+shoulders"] = features["head"] + features["shoulders"]
    features["strength*head"] = features["strength"] * features["head"]
    features["strength*(head+shoulders)"] = features["strength"] * (features["head"] + features["shoulders"])
    print(f"{path}: {len(rows)} added, {label.sum()} someone")
    for name, values in features.items():
        print(f"  {name:28s} AUC {roc_auc_score(label, values):.3f}  someone median {np.median(values[label]):.3f}"
              f"  nobody median {np.median(values[~label]):.3f}")
