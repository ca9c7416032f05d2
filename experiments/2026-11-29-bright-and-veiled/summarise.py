"""Bright and veiled frames on PETS09's choosing and confirming halves (three compile seeds) and TUD-Stadtmitte's
halves, every bundle int8 as the compile ships it: 0016's bundles under 0016's code (``results/*/0016``), the same
bundles under today's fitness (``fitness``), and bundles compiled over the range to +2 stops under today's fitness
(``range``). One table per camera and variant from the robustness benchmark's reports, and AP50 per condition
(frozen experiment, issue 62).

    python experiments/2026-11-29-bright-and-veiled/summarise.py   # reads results/{pets,tud}/*/*/robustness.json
"""

from __future__ import annotations

import importlib.util
from pathlib import Path

RESULTS = Path(__file__).parent / "results"
VARIANTS = {"0016": "0016's bundles and code", "fitness": "0016's bundles, today's fitness",
            "range": "compiled to +2 stops, today's fitness"}
#: The weather-and-gain experiment's tables (a row per run, the mean per half; AP50 per condition), reused as they are.
_WEATHER = importlib.util.spec_from_file_location(
    "weather_and_gain_summary", Path(__file__).parent.parent / "2026-11-29-weather-and-gain" / "summarise.py")
weather = importlib.util.module_from_spec(_WEATHER)
_WEATHER.loader.exec_module(weather)


def main() -> None:
    for camera in ("pets", "tud"):
        lines: list[str] = []
        variants = {name: weather._reports(RESULTS / camera / name) for name in VARIANTS}
        for name, reports in variants.items():
            if reports:
                lines += [f"**{VARIANTS[name]}** (`results/{camera}/{name}/`):", ""] + weather._table(reports) + [""]
        if not lines:
            continue
        for name in ("range", "0016"):
            if variants[name]:
                lines += [f"AP50 per condition, {VARIANTS[name]} (the bundle's fitness states over the frames; false "
                          "people on the empty background):", ""] + weather._per_condition(variants[name]) + [""]
        text = "\n".join(lines)
        (RESULTS / f"{camera}_halves.md").write_text(text)
        print(text)


if __name__ == "__main__":
    main()
