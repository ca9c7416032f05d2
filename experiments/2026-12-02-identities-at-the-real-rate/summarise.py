"""Each arm's IDF1, identity switches, AP50 tracked and pose agreement tracked, mean of the seeds per camera and half,
with each seed's IDF1 change from as shipped (frozen).

    python experiments/2026-12-02-identities-at-the-real-rate/summarise.py results/arms.jsonl > results/summary.md
"""

import json
import sys

import numpy as np


def main() -> None:
    rows = [json.loads(line) for line in open(sys.argv[1]) if line.strip()]
    arms = [key for key, value in rows[0].items() if isinstance(value, dict)]
    for camera in dict.fromkeys(row["camera"] for row in rows):
        print(f"## {camera}\n")
        print("| arm | half | IDF1 | IDF1 change per seed | identity switches (summed) | AP50 tracked | pose tracked |")
        print("|---|---|---|---|---|---|---|")
        for arm in arms:
            for half in ("choosing", "confirming"):
                mine = [row for row in rows if row["camera"] == camera and row["half"] == half]
                mean = {key: np.mean([row[arm][key] for row in mine]) for key in ("idf1", "ap50", "pose")}
                change = " / ".join(f"{row[arm]['idf1'] - row['as shipped']['idf1']:+.3f}" for row in mine)
                switches = sum(row[arm]["id_switches"] for row in mine)
                print(f"| {arm} | {half} | {mean['idf1']:.3f} | {change} | {switches} | {mean['ap50']:.3f} | "
                      f"{mean['pose']:.3f} |")
        print()


if __name__ == "__main__":
    main()
