"""What realism costs and buys: the renders' light and camera effects switched off one at a time.

    python -m benchmarks.effects_ablation --scene SCENE [--value VALUE ...] [--work DIR]
        [--dev-video V --dev-gt GT.txt --dev-frames 1:400:5] [--out benchmarks/results/accuracy_vs_time]
        [--ablation-out benchmarks/results/effects_ablation] [--no-runtime]

Runs the ``photometry`` knob of the accuracy-vs-time sweep (:mod:`benchmarks.accuracy_vs_time`, whose report in
``--out`` it joins): the standard compile with photometric matching off (the default sun, no camera effects), with
the light estimated from the background alone, matched (the standard compile), and matched less each camera effect.
Each point is a full standard compile (about an hour on 2 cores), kept in ``--work`` and resumed like every sweep
point. A value that renders what another does is that compile, measured once: matched less an effect the scene does
not call for is matched, and matched less the scene's only camera effect is the light alone. "off" is the compile
every other knob's points were measured with before photometric matching; the report takes it from there.

Beside the sweep's numbers (real and synthetic AP50, PCKh, compile minutes, runtime) it writes what each variant
costs to render: ms per sample over the whole render, and the plan's measured cost of each effect that was on,
to ``effects_ablation.json`` and ``effects_ablation.md`` in ``--ablation-out``.
"""

from __future__ import annotations

import json
from pathlib import Path

from benchmarks import accuracy_vs_time as sweep
from benchmarks import results_folder
from benchmarks.protocol import halves_cell
from vc.io import atomic_path, write_json


def render_costs(work: Path, point: sweep.Point) -> dict:
    """The render's ms per sample (all regions) and each effect's planned ms per sample, from the renders."""
    renders = work / "renders" / point.render_key()
    summary_path, manifest_path = renders / "render_summary.json", renders / "manifest.json"
    if not manifest_path.is_file():
        return {}
    manifest = json.loads(manifest_path.read_text())
    samples = sum(region["counts"]["samples"] for region in manifest["regions"].values() if "counts" in region)
    seconds_record = work / "renders" / f"{point.render_key()}.seconds.json"
    # the measured costs are in the render summary (the manifest keeps only what the pixels depend on)
    summary = json.loads(summary_path.read_text()) if summary_path.is_file() else {}
    effects = summary.get("effects", manifest.get("effects", []))
    result = {"effects_on": {effect["name"]: effect.get("ms_per_sample") for effect in effects if effect["on"]},
              "lighting": manifest.get("lighting", {}).get("illumination"), "plan_seconds": summary.get("plan_seconds")}
    if seconds_record.is_file() and samples:
        result["render_ms_per_sample"] = 1000.0 * json.loads(seconds_record.read_text())["seconds"] / samples
    return result


def report(rows: list[dict], out: Path) -> None:
    write_json(out / "effects_ablation.json", rows)
    lines = ["| renders | what they leave out | real AP50 | real AP50 choosing / confirming | synthetic AP50 | "
             "synthetic PCKh | render ms/sample | effects on (ms/sample each) | compile min |",
             "|---|---|---|---|---|---|---|---|---|"]
    for row in rows:
        real = f"{row['real_ap50']:.3f}" if "real_ap50" in row else "—"
        render = f"{row['render_ms_per_sample']:.0f}" if "render_ms_per_sample" in row else "—"
        effects = ", ".join(f"{name} ({ms:.1f})" if ms is not None else name
                            for name, ms in row.get("effects_on", {}).items()) or "—"
        what = sweep.PHOTOMETRY[row["value"]]
        if "same_as" in row:
            what += f": the same renders as {row['same_as']} (this scene calls for no more)"
        elif "measured_as" in row:
            what += f" (the sweep's point {row['measured_as']}: the same compile)"
        lines.append(f"| {row['value']} | {what} | {real} | {halves_cell(row)} | {row['synthetic_ap50']:.3f} | "
                     f"{row['synthetic_pckh']:.3f} | {render} | {effects} | {row['compile_minutes']:.1f} |")
    with atomic_path(out / "effects_ablation.md") as temporary:
        temporary.write_text("\n".join(lines) + "\n")


def measured_elsewhere(results: dict[str, list[dict]], value: str) -> dict | None:
    """A photometry value's compile measured under another knob (renders "off" are every point measured before
    photometric matching), named by where it was measured."""
    wanted = sweep.KNOBS["photometry"][value].bundle_key()
    found = next((point for point in sweep.distinct_compiles(results) if sweep.identity(point) == wanted), None)
    return None if found is None else found | {"value": value, "measured_as": found["name"]}


def main(argv: list[str] | None = None) -> None:
    parser = sweep.build_parser(knob="photometry")
    parser.add_argument("--ablation-out", type=Path, default=results_folder("effects_ablation"),
                        help="where this benchmark's own report goes (the sweep's goes to --out)")
    args = sweep.run(parser, argv)
    results = json.loads((args.out / "accuracy_vs_time.json").read_text())
    by_value = {point["value"]: point for point in results.get("photometry", [])}
    rows = []
    for value in sweep.PHOTOMETRY:
        point = by_value.get(value) or measured_elsewhere(results, value)
        if point is not None:
            rendered_as = sweep.KNOBS["photometry"][point.get("same_as", value)]
            rows.append({**point, **render_costs(args.work, rendered_as)})
    report(rows, args.ablation_out)


if __name__ == "__main__":
    main()
