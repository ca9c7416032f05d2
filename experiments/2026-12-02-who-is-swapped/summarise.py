"""Tables of results/swapped.jsonl: people and swapped people summed over the seeds, per camera, half and what
ordered them; the agreement lost to the swap, mean of the seeds and each seed's (frozen).

    python experiments/2026-12-02-who-is-swapped/summarise.py results/swapped.jsonl > results/summary.md
"""

import json
import sys

EMPTY = {"people": 0, "swapped": 0, "lost": 0.0}


def main() -> None:
    rows = [json.loads(line) for line in open(sys.argv[1]) if line.strip()]
    for camera in ("pets", "tud"):
        mine = [row for row in rows if row["camera"] == camera]
        print(f"## {camera}, seeds {', '.join(str(row['seed']) for row in mine if row['half'] == 'choosing')}\n")
        print("| ordered by | half | people | swapped | share swapped | agreement lost to the swap | lost per seed |")
        print("|---|---|---|---|---|---|---|")
        for cell in sorted({cell for row in mine for cell in row["cells"]}):
            for half in ("choosing", "confirming"):
                got = [row["cells"].get(cell, EMPTY) for row in mine if row["half"] == half]
                people, swapped = sum(g["people"] for g in got), sum(g["swapped"] for g in got)
                per_seed = " / ".join(f"{g['lost']:.3f}" for g in got)
                print(f"| {cell} | {half} | {people} | {swapped} | {swapped / max(people, 1):.2f} | "
                      f"{sum(g['lost'] for g in got) / len(got):.3f} | {per_seed} |")
        print()


if __name__ == "__main__":
    main()
