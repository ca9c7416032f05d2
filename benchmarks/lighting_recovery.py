"""How well the light is recovered from one background: the demo layout rendered under known suns and skies.

    python -m benchmarks.lighting_recovery [--scale 0.5] [--out benchmarks/results/lighting_recovery]

Each case renders the demo scene's layout through its camera (scaled by ``--scale``) with Mitsuba under a known
sun and sky, then estimates the light from that image alone (:func:`vc.calibration.lighting.estimate_lighting`)
and compares: the angle between the true and the found sun, the sun/sky ratio, the sky's luminance, and whether
an overcast sky is called overcast. Writes ``lighting_recovery.json`` and ``lighting_recovery.md`` to ``--out``.
``tests/test_lighting.py`` asserts the targets (within 10 degrees, ratio within 20 %) on the same cases.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

from benchmarks import EXAMPLE_SCENES, results_folder
from vc.calibration.lighting import Illumination, LightingEstimate, estimate_lighting, ground_view
from vc.calibration.lighting import illumination_from_strengths as light
from vc.calibration.materials import luminance
from vc.calibration.response import Response
from vc.io import write_json
from vc.render.background import render_background
from vc.render.relight import layout_solids, sun_angle_error_deg
from vc.scenes.loader import Scene, load_scene

#: (name, true light): the demo's own afternoon sun, a high one, a low one against the camera, an overcast sky.
CASES: dict[str, Illumination] = {
    "afternoon (215, 40 deg)": light(215.0, 40.0, 4.0, 1.0),
    "high (100, 62 deg)": light(100.0, 62.0, 3.0, 1.0),
    "low (320, 16 deg)": light(320.0, 16.0, 5.0, 1.0),
    "overcast": light(0.0, 45.0, 0.0, 2.5),
}


def recover(scene: Scene, truth: Illumination, scale: float = 0.5, spp: int = 16) -> tuple[LightingEstimate, dict]:
    """Render ``scene``'s layout under ``truth`` and estimate the light from the image; (estimate, errors)."""
    camera = scene.camera.resized(round(scene.camera.width * scale), round(scene.camera.height * scale))
    image = render_background(camera, scene.layout, truth, spp=spp, seed=3)
    clipped = image.max(axis=-1) == 255
    solids = layout_solids(scene.layout)
    view = ground_view(camera, Response("srgb").decode(image), clipped, scene.layout.walkable_area(), solids)
    started = time.perf_counter()
    estimate = estimate_lighting(camera, view, solids)
    found = estimate.illumination
    errors = {"seconds": round(time.perf_counter() - started, 2), "sun_source": estimate.sun_source,
              "true_sun_to_sky": round(truth.sun_to_sky, 3), "found_sun_to_sky": round(found.sun_to_sky, 3),
              "sky_luminance_error": round(luminance(found.sky_rgb) / luminance(truth.sky_rgb) - 1.0, 4)}
    if truth.has_sun and found.has_sun:
        errors["sun_direction_error_deg"] = round(sun_angle_error_deg(found, truth), 2)
        errors["sun_to_sky_error"] = round(found.sun_to_sky / truth.sun_to_sky - 1.0, 4)
    return estimate, errors


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--scale", type=float, default=0.5, help="camera scale (default 0.5: 480x270)")
    parser.add_argument("--out", type=Path, default=results_folder("lighting_recovery"))
    args = parser.parse_args()
    scene = load_scene(EXAMPLE_SCENES / "demo" / "scene.yaml")
    rows = []
    for name, truth in CASES.items():
        _, errors = recover(scene, truth, args.scale)
        rows.append({"case": name, **errors})
        print(rows[-1])
    write_json(args.out / "lighting_recovery.json", rows)
    lines = ["| true light | found | sun direction error | sun/sky true → found | sky luminance error | estimate s |",
             "|---|---|---|---|---|---|"]
    for row in rows:
        direction = f"{row['sun_direction_error_deg']:.1f}°" if "sun_direction_error_deg" in row else "—"
        ratio = f"{row['true_sun_to_sky']:.2f} → {row['found_sun_to_sky']:.2f}"
        lines.append(f"| {row['case']} | {row['sun_source']} | {direction} | {ratio} | "
                     f"{row['sky_luminance_error']:+.1%} | {row['seconds']:.1f} |")
    (args.out / "lighting_recovery.md").write_text("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
