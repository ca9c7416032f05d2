"""What albedo the background implies for its ground under the estimated light, by kind and by view angle: why
one albedo prior per kind of ground cannot bring the re-rendered empty scene within 10 % of the background in
every region.

The lighting fit (``render/relight.py``) re-renders the empty scene under the estimate, gives each known-ground
pixel the prior albedo of its kind (``calibration/materials.py``: paved 0.31, vegetation 0.12 luminance) and fits
one exposure. Where the re-render and the background differ, the background implies another albedo:
``prior x background / re-render``. This script reports that implied albedo (median and quartiles) per kind of
ground, per band of view elevation (the angle between the camera's ray and the ground: low is grazing, far away),
and per region.

    python experiments/2026-11-26-ground-albedo/ground_albedo.py --scene examples/scenes/pets09_s2l1/scene.yaml
        [--out experiments/2026-11-26-ground-albedo/results] [--name pets09]

Writes ``ground_albedo_<name>.json``, ``.md`` and ``.png`` (implied albedo against view elevation, per kind).
"""

from __future__ import annotations

import argparse
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from vc.calibration.camera import Camera  # noqa: E402
from vc.calibration.materials import PAVED_ALBEDO, VEGETATION_ALBEDO, luminance  # noqa: E402
from vc.errors import InputError  # noqa: E402
from vc.io import write_json  # noqa: E402
from vc.render.relight import region_mask, solve_lighting  # noqa: E402
from vc.scenes.loader import load_scene  # noqa: E402
from vc.scenes.regions import plan_regions  # noqa: E402

#: Bands of view elevation (degrees) the implied albedo is reported in.
ELEVATION_BANDS = tuple(range(0, 95, 5))
#: A band is reported when it holds at least this many known-ground pixels of the kind.
MIN_PIXELS = 500
PRIORS = {"paved": float(luminance(PAVED_ALBEDO)), "vegetation": float(luminance(VEGETATION_ALBEDO))}


def view_elevation_deg(camera: Camera) -> np.ndarray:
    """(H, W) angle between each pixel's ray and the ground plane where the ray meets it (NaN elsewhere); pixel
    centres at integers, the camera's convention."""
    rows, columns = np.indices((camera.height, camera.width))
    hit = camera.ground_from_pixels(np.stack([columns.ravel(), rows.ravel()], axis=1).astype(float))
    distance = np.linalg.norm(hit.points[:, :2] - camera.center[:2], axis=1)
    elevation = np.degrees(np.arctan2(camera.center[2], distance))
    return np.where(hit.ok, elevation, np.nan).reshape(camera.height, camera.width)


def _summary(values: np.ndarray) -> dict:
    quartiles = np.percentile(values, [25, 50, 75])
    return {"pixels": int(len(values)), "median": float(quartiles[1]), "p25": float(quartiles[0]),
            "p75": float(quartiles[2])}


def implied_albedo(scene_path: Path) -> dict:
    scene = load_scene(scene_path)
    regions = plan_regions(scene)
    fit = solve_lighting(scene, regions).fit
    known = fit.known_ground
    kinds = {"vegetation": known & fit.vegetation, "paved": known & ~fit.vegetation}
    prior = np.where(fit.vegetation, PRIORS["vegetation"], PRIORS["paved"])
    with np.errstate(divide="ignore", invalid="ignore"):
        implied = prior * fit.background_luminance / luminance(fit.rendered)
    elevation = view_elevation_deg(scene.camera)
    result = {"scene": scene.name, "priors": PRIORS, "by_kind": {}, "by_elevation": {}, "by_region": {}}
    for kind, mask in kinds.items():
        result["by_kind"][kind] = _summary(implied[mask]) if mask.any() else None
        bands = []
        for low, high in zip(ELEVATION_BANDS, ELEVATION_BANDS[1:], strict=False):
            band = mask & (elevation >= low) & (elevation < high)
            if band.sum() >= MIN_PIXELS:
                bands.append({"elevation_deg": [low, high], **_summary(implied[band])})
        result["by_elevation"][kind] = bands
    for region in regions:
        inside = region_mask(scene.camera, region)
        result["by_region"][region.name] = {kind: _summary(implied[mask & inside]) if (mask & inside).sum() else None
                                            for kind, mask in kinds.items()}
    return result


def write_report(result: dict, out: Path, name: str) -> None:
    write_json(out / f"ground_albedo_{name}.json", result)
    lines = [f"Ground albedo implied by the background of {result['scene']} under its estimated light (prior x "
             "background / re-render; `python experiments/2026-11-26-ground-albedo/ground_albedo.py`).", "",
             "| kind | prior | implied, all (median, IQR) | by view elevation (median) |", "|---|---|---|---|"]
    for kind, summary in result["by_kind"].items():
        if summary is None:
            continue
        bands = ", ".join(f"{b['elevation_deg'][0]}–{b['elevation_deg'][1]}°: {b['median']:.3f}"
                          for b in result["by_elevation"][kind])
        lines.append(f"| {kind} | {result['priors'][kind]:.3f} | {summary['median']:.3f} ({summary['p25']:.3f}–"
                     f"{summary['p75']:.3f}) | {bands} |")
    lines += ["", "| region | paved (median, pixels) | vegetation (median, pixels) |", "|---|---|---|"]
    for region, kinds in result["by_region"].items():
        cells = [f"{kinds[k]['median']:.3f} ({kinds[k]['pixels']})" if kinds[k] else "—"
                 for k in ("paved", "vegetation")]
        lines.append(f"| {region} | {cells[0]} | {cells[1]} |")
    (out / f"ground_albedo_{name}.md").write_text("\n".join(lines) + "\n")

    figure, axis = plt.subplots(figsize=(6.4, 4.0))
    for kind, colour in (("paved", "tab:grey"), ("vegetation", "tab:green")):
        bands = result["by_elevation"][kind]
        if not bands:
            continue
        middle = [np.mean(b["elevation_deg"]) for b in bands]
        axis.errorbar(middle, [b["median"] for b in bands],
                      yerr=[[b["median"] - b["p25"] for b in bands], [b["p75"] - b["median"] for b in bands]],
                      color=colour, marker="o", capsize=3, label=f"{kind}, implied (median, IQR)")
        axis.axhline(result["priors"][kind], color=colour, linestyle="--", label=f"{kind}, prior")
    axis.set_xlabel("view elevation (degrees; low = grazing, far from the camera)")
    axis.set_ylabel("ground albedo (luminance)")
    axis.set_title(f"{result['scene']}: albedo the background implies under the estimated light")
    axis.legend(fontsize=8)
    figure.tight_layout()
    figure.savefig(out / f"ground_albedo_{name}.png", dpi=120)
    plt.close(figure)


def main(argv: list[str] | None = None) -> int:
    """A scene that cannot be read or lit gets one line and exit status 2 (the project's input contract)."""
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--scene", type=Path, required=True)
    parser.add_argument("--out", type=Path, default=Path(__file__).parent / "results")
    parser.add_argument("--name", default=None, help="results file suffix (default: the scene's name)")
    args = parser.parse_args(argv)
    try:
        result = implied_albedo(args.scene)
    except InputError as error:
        parser.error(str(error))
    write_report(result, args.out, args.name or result["scene"])
    for kind, summary in result["by_kind"].items():
        if summary:
            print(f"{kind}: implied albedo {summary['median']:.3f} ({summary['p25']:.3f}-{summary['p75']:.3f}), "
                  f"prior {result['priors'][kind]:.3f}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
