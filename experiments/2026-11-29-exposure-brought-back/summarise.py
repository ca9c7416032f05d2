"""Light beyond the range brought back, on PETS09's choosing and confirming halves (three compile seeds) and
TUD-Stadtmitte's halves (seed 0), every bundle int8 as the compile ships it: the same bundles under 0017's runtime
(``../2026-11-29-bright-and-veiled/results/*/fitness_final``) and under the runtime that brings a frame lit beyond
the range back (``results/*/brought_back``). One table per camera and runtime from the robustness benchmark's
reports, and AP50 per condition (frozen experiment, issue 62).

    python experiments/2026-11-29-exposure-brought-back/summarise.py   # writes results/{pets,tud}_halves.md
"""

from __future__ import annotations

import importlib.util
from pathlib import Path

HERE = Path(__file__).parent
RESULTS = HERE / "results"
VARIANTS = {"before": ("0017's runtime (the frame withheld)", HERE.parent / "2026-11-29-bright-and-veiled" / "results",
                       "fitness_final"),
            "brought_back": ("light beyond the range brought back", RESULTS, "brought_back")}
#: The weather-and-gain experiment's tables (a row per run, the mean per half; AP50 per condition), reused as they are.
_WEATHER = importlib.util.spec_from_file_location(
    "weather_and_gain_summary", HERE.parent / "2026-11-29-weather-and-gain" / "summarise.py")
weather = importlib.util.module_from_spec(_WEATHER)
_WEATHER.loader.exec_module(weather)


def main() -> None:
    for camera in ("pets", "tud"):
        lines: list[str] = []
        for label, root, name in VARIANTS.values():
            reports = weather._reports(root / camera / name)
            if reports:
                lines += [f"**{label}** (`{(root / camera / name).relative_to(HERE.parent)}/`):", ""] \
                    + weather._table(reports) + ["", f"AP50 per condition, {label}:", ""] \
                    + weather._per_condition(reports) + [""]
        text = "\n".join(lines)
        (RESULTS / f"{camera}_halves.md").write_text(text)
        print(text)


if __name__ == "__main__":
    main()
