"""The bundled scenes load, plan and keep their promises (the demo renders its own background; its dated copy
differs from it only in saying where and when instead of where the sun is)."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import EXAMPLE_SCENES

from vc.io import read_image
from vc.scenes.loader import load_scene
from vc.scenes.regions import plan_regions


def test_demo_scene_is_self_contained_and_in_view():
    scene = load_scene(EXAMPLE_SCENES / "demo" / "scene.yaml")
    assert scene.image_path.parent == EXAMPLE_SCENES / "demo"
    camera = scene.camera
    for blocker in scene.layout.blockers():
        projection = camera.project(blocker.edges().reshape(-1, 3))
        assert projection.ok.all() and camera.is_in_image(projection.uv).all(), blocker.name
    regions = plan_regions(scene)
    assert len(regions) >= 2
    assert all(r.person_px[0] >= 16 for r in regions)


def test_the_dated_demo_is_the_demo_with_where_and_when_for_its_sun():
    import yaml

    from vc.render.relight import known_sun

    demo, dated = (yaml.safe_load((EXAMPLE_SCENES / name / "scene.yaml").read_text())
                   for name in ("demo", "demo_dated"))
    differ = ("name", "image", "lighting")
    assert {key: value for key, value in dated.items() if key not in differ} == \
        {key: value for key, value in demo.items() if key not in differ}
    scene = load_scene(EXAMPLE_SCENES / "demo_dated" / "scene.yaml")
    assert scene.image_path == load_scene(EXAMPLE_SCENES / "demo" / "scene.yaml").image_path
    assert set(dated["lighting"]) == {"location", "time", "north_deg"}
    azimuth, elevation = known_sun(scene.lighting)
    assert (azimuth, elevation) == pytest.approx((demo["lighting"]["sun_azimuth_deg"],
                                                  demo["lighting"]["sun_elevation_deg"]), abs=0.5)


@pytest.mark.slow
def test_demo_background_is_the_render_of_its_layout():
    from vc.render.background import render_background
    from vc.render.relight import explicit_illumination

    scene = load_scene(EXAMPLE_SCENES / "demo" / "scene.yaml")
    rendered = render_background(scene.camera, scene.layout, explicit_illumination(scene.lighting), spp=128, seed=0)
    shipped = read_image(scene.image_path)
    # Same seed, same bytes on one machine; allow for LLVM code generation differing between CPUs.
    assert np.abs(rendered.astype(int) - shipped.astype(int)).mean() < 1.0


def test_pets_scene_loads_with_the_shared_background(pets_data):
    scene = load_scene(EXAMPLE_SCENES / "pets09_s2l1" / "scene.yaml")
    assert scene.image_path == (pets_data / "background.png").resolve()
    assert scene.camera.size == (768, 576)
    names = [o.name for o in scene.layout.obstacles]
    assert "lamp post" in names and "tripod (near)" in names
