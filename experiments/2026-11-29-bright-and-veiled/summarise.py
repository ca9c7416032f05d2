"""Bright and veiled frames on PETS09's choosing and confirming halves (three compile seeds) and TUD-Stadtmitte's
halves, every bundle int8 as the compile ships it: 0016's bundles under 0016's code (``results/*/0016``), the same
bundles under the fitness that tells another view by its structure (``fitness``) and under the final fitness
(``fitness_final``), bundles compiled over the range to +2 stops under the first (``range``; ``range_flag``: every
frame run) and under the final one, which also asks the structure before the cells' light and reads greying apart
from a cast (``final``). One table per camera and variant from the robustness benchmark's reports, and AP50 per
condition (frozen experiment, issue 62).

    python experiments/2026-11-29-bright-and-veiled/summarise.py   # reads results/{pets,tud}/*/*/robustness.json
"""

from __future__ import annotations

import importlib.util
from pathlib import Path

RESULTS = Path(__file__).parent / "results"
VARIANTS = {"0016": "0016's bundles and code", "fitness": "0016's bundles, another view by its structure",
            "fitness_final": "0016's bundles, the final fitness (TUD-Stadtmitte: not compiled to +2 stops)",
            "range": "compiled to +2 stops, another view by its structure",
            "range_flag": "compiled to +2 stops, every frame run (the networks alone)",
            "final": "compiled to +2 stops, the final fitness (also: the structure before the light, greying no cast)"}
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
        for name in ("final", "range", "0016"):
            if variants[name]:
                lines += [f"AP50 per condition, {VARIANTS[name]} (the bundle's fitness states over the frames; false "
                          "people on the empty background):", ""] + weather._per_condition(variants[name]) + [""]
        text = "\n".join(lines)
        (RESULTS / f"{camera}_halves.md").write_text(text)
        print(text)


if __name__ == "__main__":
    main()
