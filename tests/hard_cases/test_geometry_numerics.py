"""Camera maths at any pose and the training targets of any person: what every label and every heat map is made
of. Cameras anywhere from 0.3 m to 60 m up, looking anywhere but straight up or down, with lenses from fisheye
to telephoto and Town Centre-like distortion; people of any size, anywhere on or off the input, keypoints
unlabelled or far outside it. No NaN or inf comes out except as a flagged miss, and targets stay in range."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
from hard_case_settings import PROPERTY
from hypothesis import assume, example, given
from hypothesis import strategies as st
from scene_factory import base_scene, write_scene

from vc.calibration.camera import Camera, look_at
from vc.calibration.distortion import BrownConrady
from vc.deploy.heatmaps import CENTRE_CHANNEL, HANDEDNESS_CHANNELS, KEYPOINT_CHANNELS, MASK_CHANNEL, PAIRS
from vc.errors import InputError
from vc.model.codec import CodecConfig, encode
from vc.scenes.loader import Scene, load_scene
from vc.scenes.regions import plan_regions

WIDTH, HEIGHT = 640, 480
finite = {"allow_nan": False, "allow_infinity": False}


@st.composite
def cameras(draw) -> Camera:
    eye = np.array([draw(st.floats(-50, 50)), draw(st.floats(-50, 50)), draw(st.floats(0.3, 60))])
    target = np.array([draw(st.floats(-100, 100)), draw(st.floats(-100, 100)), draw(st.floats(-5, 5))])
    direction = target - eye
    assume(np.linalg.norm(direction) > 1e-3 and np.linalg.norm(direction[:2]) > 1e-4 * np.linalg.norm(direction))
    R, t = look_at(eye, target, draw(st.floats(-30, 30)))
    focal = draw(st.floats(50, 5000))
    K = np.array([[focal, 0, (WIDTH - 1) / 2], [0, focal, (HEIGHT - 1) / 2], [0, 0, 1]])
    lens = draw(st.sampled_from(["none", "barrel", "town centre"]))
    distortion = {"none": BrownConrady(0.0, 0.0, 0.0, 0.0), "barrel": BrownConrady(-0.3, 0.08, 0.0, 0.0),
                  "town centre": BrownConrady(-0.6015, 4.7020, -0.000475, -0.007823)}[lens]
    return Camera(WIDTH, HEIGHT, K=K, R=R, t=t, distortion=distortion)


@PROPERTY
@given(camera=cameras(), point=st.tuples(st.floats(-1e4, 1e4), st.floats(-1e4, 1e4), st.floats(-1e3, 1e3)))
def test_projection_at_any_pose_is_finite_exactly_where_flagged(camera, point):
    projection = camera.project(np.array([point]))
    assert np.isfinite(projection.uv[0]).all() == bool(projection.ok[0])


@PROPERTY
@given(camera=cameras(), u=st.floats(-2 * WIDTH, 3 * WIDTH), v=st.floats(-2 * HEIGHT, 3 * HEIGHT))
def test_ground_hits_at_any_pose_are_finite_on_the_ground_or_flagged(camera, u, v):
    hit = camera.ground_from_pixels(np.array([[u, v]]))
    if hit.ok[0]:
        assert np.isfinite(hit.points[0]).all() and abs(hit.points[0, 2]) < 1e-6 * max(1.0, abs(hit.points[0]).max())
    else:
        assert np.isnan(hit.points[0]).all()


@st.composite
def people(draw, index: int) -> dict:
    size = 128
    height = draw(st.floats(0.5, 50 * size, **finite))
    centre = draw(st.one_of(st.none(), st.tuples(st.floats(-10 * size, 11 * size), st.floats(-10 * size, 11 * size))))
    keypoints = []
    for _ in range(17):
        keypoints += [draw(st.floats(-1e5, 1e5)), draw(st.floats(-1e5, 1e5)), draw(st.sampled_from([0, 1, 2]))]
    return {"center": None if centre is None else list(centre), "keypoints": keypoints,
            "amodal_bbox": [0.0, 0.0, height / 2, height], "instance_id": index + 1,
            "left_is_image_left": draw(st.one_of(st.none(), st.lists(st.booleans(), min_size=len(PAIRS),
                                                                     max_size=len(PAIRS))))}


@st.composite
def samples(draw) -> tuple[list[dict], np.ndarray]:
    count = draw(st.integers(0, 4))
    annotations = [draw(people(index)) for index in range(count)]
    instances = np.zeros((128, 128), np.uint8)
    for annotation in annotations:
        x0, y0 = draw(st.integers(0, 127)), draw(st.integers(0, 127))
        instances[y0:y0 + draw(st.integers(0, 128)), x0:x0 + draw(st.integers(0, 128))] = annotation["instance_id"]
    return annotations, instances


@PROPERTY
@given(sample=samples(), stride=st.sampled_from([1, 2, 4]))
def test_targets_of_any_people_are_finite_and_in_range(sample, stride):
    annotations, instances = sample
    maps = encode(annotations, instances, CodecConfig(stride=stride))
    assert maps.shape[1:] == (128 // stride, 128 // stride) and np.isfinite(maps).all()
    peaks = maps[[CENTRE_CHANNEL, *range(KEYPOINT_CHANNELS.start, KEYPOINT_CHANNELS.stop), MASK_CHANNEL]]
    assert peaks.min() >= 0.0 and peaks.max() <= 1.0
    assert np.abs(maps[HANDEDNESS_CHANNELS]).max(initial=0.0) <= 1.0 + 1e-6


@pytest.fixture(scope="module")
def unit_scene(tmp_path_factory) -> Scene:
    return load_scene(write_scene(tmp_path_factory.mktemp("scene"), base_scene()))


#: Found by the thorough runs: a fisheye seeing 0.06 m2 of the walkable area, which fell apart into sliver bands.
FISHEYE_ON_A_SLIVER = Camera(WIDTH, HEIGHT, K=np.array([[50.0, 0, 319.5], [0, 50.0, 239.5], [0, 0, 1]]),
                             R=np.array([[0.90718823, -0.42072498, 0.0], [-0.04400961, -0.09489571, -0.99451393],
                                         [0.41841685, 0.90221134, -0.10460421]]),
                             t=np.array([-3.62875294, 0.17603842, 7.88617699]),
                             distortion=BrownConrady(-0.6015, 4.702, -0.000475, -0.007823))
#: ... and a camera 12 m up looking down with a foot sample exactly below it (a person zero pixels tall).
TOP_DOWN_OVER_A_SAMPLE = Camera(WIDTH, HEIGHT, K=np.array([[87.0, 0, 319.5], [0, 87.0, 239.5], [0, 0, 1]]),
                                R=np.array([[1.0, 0.0, 0.0], [0.0, -0.99654576, -0.08304548],
                                            [0.0, 0.08304548, -0.99654576]]),
                                t=np.array([0.0, 0.99654576, 11.9585491]), distortion=BrownConrady(0, 0, 0, 0))
#: ... and a fisheye 2.5 m up whose Town Centre lens casts heads to finite but enormous pixels (1e20).
FISHEYE_CASTING_HEADS_FAR = Camera(WIDTH, HEIGHT, K=np.array([[50.0, 0, 319.5], [0, 50.0, 239.5], [0, 0, 1]]),
                                   R=np.array([[-1.0, 0.0, 0.0], [0.0, 0.8, -0.6], [0.0, -0.6, -0.8]]),
                                   t=np.array([0.0, 0.0, 2.5]), distortion=BrownConrady(-0.6015, 4.702, -0.000475,
                                                                                        -0.007823))


@PROPERTY
@given(camera=cameras())
@example(camera=FISHEYE_ON_A_SLIVER)
@example(camera=TOP_DOWN_OVER_A_SAMPLE)
@example(camera=FISHEYE_CASTING_HEADS_FAR)
def test_region_planning_at_any_pose_is_finite_or_refused(unit_scene, camera):
    """The unit scene's layout seen from anywhere: regions whose people, crops and inputs are finite and inside
    the image, or one InputError (nothing walkable in view, people too small everywhere), never anything else."""
    scene = replace(unit_scene, camera=camera)
    try:
        regions = plan_regions(scene)
    except InputError:
        return
    assert regions
    for region in regions:
        assert np.isfinite([*region.person_px, *region.reference_px]).all() and 0 < region.person_px[0]
        x, y, width, height = region.crop.to_list()
        assert 0 <= x and 0 <= y and x + width <= WIDTH and y + height <= HEIGHT and width > 0 and height > 0
        assert min(region.input_size) > 0
