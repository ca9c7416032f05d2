"""Region planning: bands respect the height ratio, partition the visible walkable ground, crops hold people."""

from __future__ import annotations

import numpy as np
import pytest
import shapely
from scene_factory import modified, write_scene

from vc.errors import InputError
from vc.scenes.loader import load_scene
from vc.scenes.regions import plan_regions, planning_domain, region_map, sample_ground


@pytest.fixture(scope="module")
def unit_scene(tmp_path_factory):
    return load_scene(write_scene(tmp_path_factory.mktemp("unit")))


@pytest.fixture(scope="module")
def unit_regions(unit_scene):
    return plan_regions(unit_scene)


def test_auto_regions_respect_the_height_ratio(unit_scene, unit_regions):
    spec = unit_scene.regions
    assert len(unit_regions) >= 2
    for region in unit_regions:
        heights = unit_scene.camera.person_pixel_height(sample_ground(region.ground, 0.1), spec.reference_height_m)
        # The iso-lines come from a 320-cell grid: allow 1% of interpolation error at the band edges.
        assert np.nanmax(heights) / np.nanmin(heights) <= spec.max_height_ratio * 1.01, region.name
    reference = [r.reference_px for r in unit_regions]
    assert reference == sorted(reference), "regions are ordered far to near"


def test_regions_partition_the_visible_walkable_ground(unit_scene, unit_regions):
    domain = planning_domain(unit_scene, unit_scene.regions)
    union = shapely.union_all([r.ground for r in unit_regions])
    assert union.symmetric_difference(domain).area < 1e-6 * domain.area
    for i, a in enumerate(unit_regions):
        for b in unit_regions[i + 1:]:
            assert a.ground.intersection(b.ground).area < 1e-6
    # Obstacle footprints are not standable.
    post = unit_scene.layout.obstacles[0]
    assert not union.contains(shapely.Point(post.base))


def test_crop_windows_hold_the_tallest_person_anywhere_in_the_region(unit_scene, unit_regions):
    camera = unit_scene.camera
    tallest = unit_scene.priors.height_m[1]
    for region in unit_regions:
        feet = sample_ground(region.ground, 0.25)
        for top in (0.0, tallest):
            uv = camera.project(feet + [0, 0, top]).uv
            uv = uv[camera.is_in_image(uv)]
            crop = region.crop
            assert (uv[:, 0] >= crop.x0 - 0.5).all() and (uv[:, 0] <= crop.x1 - 0.5).all()
            assert (uv[:, 1] >= crop.y0 - 0.5).all() and (uv[:, 1] <= crop.y1 - 0.5).all()


def test_input_sizes_bring_people_to_the_target_height(unit_scene, unit_regions):
    spec = unit_scene.regions
    for region in unit_regions:
        assert all(size % spec.input_multiple == 0 for size in region.input_size)
        typical = np.sqrt(region.reference_px[0] * region.reference_px[1]) * region.scale[1]
        expected = min(spec.target_person_px, np.sqrt(np.prod(region.reference_px)) * spec.max_upscale)
        assert typical == pytest.approx(expected, rel=0.12)


def test_region_camera_is_the_crop_then_the_resize(unit_scene, unit_regions):
    camera = unit_scene.camera
    region = unit_regions[0]
    feet = sample_ground(region.ground, 0.5)
    full = camera.project(feet).uv
    local = region.camera(camera).project(feet).uv
    sx, sy = region.scale
    expected = np.c_[(full[:, 0] - region.crop.x0 + 0.5) * sx - 0.5, (full[:, 1] - region.crop.y0 + 0.5) * sy - 0.5]
    np.testing.assert_allclose(local, expected, atol=1e-9)


def test_region_map_owner_is_the_region_under_the_foot(unit_scene, unit_regions):
    camera = unit_scene.camera
    owner = region_map(camera, unit_regions)
    assert owner.shape == (camera.height, camera.width)
    for index, region in enumerate(unit_regions):
        inner = region.ground.buffer(-0.3)
        if inner.is_empty:
            continue
        uv = camera.project(sample_ground(inner, 0.4)).uv
        uv = np.round(uv[camera.is_in_image(uv)]).astype(int)
        assert (owner[uv[:, 1], uv[:, 0]] == index).mean() > 0.99
        # The owned image area (a polygon, for the bundle manifest) agrees with the per-pixel map.
        pixels = np.argwhere(owner == index)[:, ::-1]
        inside = shapely.contains_xy(region.owned_image_area, pixels[:, 0], pixels[:, 1])
        assert inside.mean() > 0.98


def test_single_region_is_the_whole_domain(tmp_path):
    scene = load_scene(write_scene(tmp_path, modified(lambda s: s.update(regions="single"))))
    (region,) = plan_regions(scene)
    domain = planning_domain(scene, scene.regions)
    assert region.name == "all" and region.ground.symmetric_difference(domain).area < 1e-9


def test_explicit_regions(tmp_path):
    polygons = [{"name": "near", "polygon": [[-8, -4], [8, -4], [8, 4], [-8, 4]]},
                {"name": "far", "polygon": [[-8, 4], [8, 4], [8, 16], [-8, 16]]}]
    scene = load_scene(write_scene(tmp_path / "ok", modified(lambda s: s.update(regions=polygons))))
    assert [r.name for r in plan_regions(scene)] == ["near", "far"]
    overlapping = [polygons[0], {"name": "far", "polygon": [[-8, 2], [8, 2], [8, 16], [-8, 16]]}]
    scene = load_scene(write_scene(tmp_path / "bad", modified(lambda s: s.update(regions=overlapping))))
    with pytest.raises(InputError, match="overlaps region 'near'"):
        plan_regions(scene)


def test_bundled_pets_scene_plans_three_depth_bands(pets_data):
    from conftest import EXAMPLE_SCENES

    scene = load_scene(EXAMPLE_SCENES / "pets09_s2l1" / "scene.yaml")
    regions = plan_regions(scene)
    assert len(regions) == 3
    # People at the far end of the walkable area are smaller than at the near end by more than 2x.
    assert regions[-1].reference_px[1] / regions[0].reference_px[0] > 2.5


def test_a_region_may_plan_its_people_at_its_own_size(tmp_path, unit_regions):
    near = unit_regions[-1].name  # its people are large: 80 px shrinks them, 40 px shrinks them twice as much
    sized = {"mode": "auto", "target_person_px": 80.0, "person_px_by_region": {near: 40.0}}
    scene = load_scene(write_scene(tmp_path / "ok", modified(lambda s: s.update(regions=sized))))
    regions = {region.name: region for region in plan_regions(scene)}
    before = {region.name: region for region in unit_regions}  # the same scene at 80 px everywhere
    assert regions[near].crop == before[near].crop  # the same ground and window, resized more
    assert regions[near].scale[1] == pytest.approx(before[near].scale[1] / 2, rel=0.1)
    assert all(regions[name].input_size == before[name].input_size for name in regions if name != near)
    unknown = {**sized, "person_px_by_region": {"nearest": 64.0}}
    scene = load_scene(write_scene(tmp_path / "bad", modified(lambda s: s.update(regions=unknown))))
    with pytest.raises(InputError, match="no region 'nearest'") as error:
        plan_regions(scene)
    assert error.value.field == "regions.person_px_by_region.nearest"
