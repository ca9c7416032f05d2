"""anny bodies: statures, grounding, body frame axes, left/right, gait, body parts, keypoints, sampling."""

from __future__ import annotations

import numpy as np
import pytest
import torch
import trimesh

from vc.deploy.decode import LOWER_ANKLE_OFFSET, UPRIGHT_OFFSETS
from vc.deploy.facing import FACE_AHEAD_OF_EARS
from vc.keypoints import COCO_KEYPOINTS
from vc.render.appearance import sample_appearance, vertex_thickness
from vc.render.bodies import BODY_PARTS, Gait, Phenotype, PosedBodies, sample_gait, sample_phenotype
from vc.render.dressing import dress

pytestmark = pytest.mark.xdist_group("anny")

K = {name: index for index, name in enumerate(COCO_KEYPOINTS)}
PAIRS = [(name, name.replace("left_", "right_")) for name in COCO_KEYPOINTS if name.startswith("left_")]
STAND, WALK, RUN = Gait(0.0, 0.3, 0.5), Gait(1.4, 0.0, 1.0), Gait(3.5, 0.0, 1.0)


def person(**changes) -> Phenotype:
    values = dict(gender=1.0, age_years=35.0, height_m=1.75, weight=0.5, muscle=0.5, proportions=0.5,
                  ethnicity=(0.2, 0.2, 0.6))
    return Phenotype(**{**values, **changes})


def varied_people(count: int, seed: int = 0) -> list[Phenotype]:
    rng = np.random.default_rng(seed)
    return [sample_phenotype(rng, (1.45, 2.05)) for _ in range(count)]


def knee_flexion_deg(keypoints: np.ndarray, side: str) -> float:
    hip, knee, ankle = (keypoints[K[f"{side}_{joint}"]] for joint in ("hip", "knee", "ankle"))
    thigh, shank = knee - hip, ankle - knee
    return float(np.degrees(np.arccos(thigh @ shank / np.linalg.norm(thigh) / np.linalg.norm(shank))))


def test_statures_reach_the_requested_height(body_model) -> None:
    people = varied_people(8) + [person(height_m=1.45, gender=0.0), person(height_m=2.05)]
    gaits = [STAND, WALK, RUN, STAND, WALK, RUN, STAND, WALK, STAND, STAND]
    posed = body_model.pose(people, gaits)
    np.testing.assert_allclose(posed.stature_m, [p.height_m for p in people], atol=1e-3)
    # A person standing is as tall as their stature, give or take the head's tilt: the scale did apply.
    standing = [k for k, gait in enumerate(gaits) if gait.speed_mps == 0]
    tops = posed.vertices[standing, :, 2].max(1)
    np.testing.assert_allclose(tops, posed.stature_m[standing], atol=0.03)


def test_bodies_stand_on_z_0_with_the_pelvis_on_the_z_axis(body_model) -> None:
    posed = body_model.pose(varied_people(3), [STAND, WALK, RUN])
    np.testing.assert_allclose(posed.vertices[..., 2].min(1), 0.0, atol=1e-3)
    shoes = posed.vertices[:, body_model.vertex_parts == BODY_PARTS.index("shoes"), 2]
    np.testing.assert_allclose(shoes.min(1), 0.0, atol=1e-3)  # on their feet
    hips = 0.5 * (posed.keypoints[:, K["left_hip"]] + posed.keypoints[:, K["right_hip"]])
    assert np.all(np.abs(hips[:, :2]) < 0.08)


def test_bodies_face_plus_x_with_their_left_on_plus_y(body_model) -> None:
    posed = body_model.pose([person()] * 3, [STAND, WALK, RUN])
    for keypoints in posed.keypoints:
        hips = 0.5 * (keypoints[K["left_hip"]] + keypoints[K["right_hip"]])
        assert keypoints[K["nose"]][0] > hips[0] + 0.05
        for left, right in PAIRS:
            assert keypoints[K[left]][1] > keypoints[K[right]][1], (left, right)


def test_gait_phase_0_puts_the_left_leg_forward_and_0_5_the_right(body_model) -> None:
    gaits = [Gait(1.4, 0.0, 1.0), Gait(1.4, 0.5, 1.0), Gait(3.0, 0.0, 1.0), Gait(3.0, 0.5, 1.0)]
    posed = body_model.pose([person()] * 4, gaits)
    for keypoints, gait in zip(posed.keypoints, gaits, strict=True):
        forward = 1.0 if gait.phase == 0.0 else -1.0
        stride = keypoints[K["left_ankle"]][0] - keypoints[K["right_ankle"]][0]
        assert forward * stride > 0.4
        # Arms swing against the legs: the right hand is ahead when the left foot is.
        assert forward * (keypoints[K["right_wrist"]][0] - keypoints[K["left_wrist"]][0]) > 0.15


def test_standing_arms_hang_beside_the_body(body_model) -> None:
    people = [person(), person(gender=0.0, height_m=1.55), person(weight=1.0, muscle=1.0, height_m=1.9),
              person(gender=0.0, weight=1.0, muscle=0.0, proportions=1.0), person(weight=0.0, muscle=0.0)]
    gaits = [Gait(0.0, phase, swing) for phase, swing in ((0.0, 0.0), (0.3, 1.0), (0.7, 0.5), (0.5, 1.0), (0.9, 0.2))]
    posed = body_model.pose(people, gaits)
    hips = body_model.vertex_parts == BODY_PARTS.index("lower")
    for vertices, keypoints, stature in zip(posed.vertices, posed.keypoints, posed.stature_m, strict=True):
        for side in ("left", "right"):
            shoulder, elbow, wrist = (keypoints[K[f"{side}_{joint}"]] for joint in ("shoulder", "elbow", "wrist"))
            assert shoulder[2] - wrist[2] > 0.28 * stature  # anny's A-pose has them 0.2 stature apart
            assert shoulder[2] - elbow[2] > 0.12 * stature  # the COCO shoulder is on top of the deltoid
            assert abs(wrist[0] - shoulder[0]) < 0.2
            # The wrist hangs just outside the hips, seen from the front.
            level = hips & (np.abs(vertices[:, 2] - wrist[2]) < 0.03)
            gap = abs(wrist[1]) - np.abs(vertices[level, 1]).max()
            assert 0.0 < gap < 0.1, (side, gap)


def test_running_bends_the_swing_knee_more_than_walking(body_model) -> None:
    # 0.7 of the cycle after its heel strike, the left leg is in mid-swing.
    posed = body_model.pose([person()] * 2, [Gait(1.4, 0.7, 1.0), Gait(3.5, 0.7, 1.0)])
    walking, running = (knee_flexion_deg(keypoints, "left") for keypoints in posed.keypoints)
    assert walking > 35.0
    assert running > walking + 25.0


def test_keypoints_lie_on_the_body(body_model) -> None:
    posed = body_model.pose(varied_people(4, seed=3), [STAND, WALK, RUN, WALK])
    low, high = posed.vertices.min(1), posed.vertices.max(1)
    assert np.all(posed.keypoints >= low[:, None] - 0.02)
    assert np.all(posed.keypoints <= high[:, None] + 0.02)


def test_keypoints_are_anny_coco_regressor_on_the_full_resolution_body(body_model) -> None:
    import anny
    from anny.keypoints import KeypointsRegressor

    people, gaits = varied_people(3, seed=5), [STAND, WALK, RUN]
    with torch.inference_mode():
        parameters, weights, rest, _, _ = body_model._shape(people)
        heads = body_model._rest_bone_heads(weights)
        pose = torch.from_numpy(body_model._pose_parameters(gaits, heads, body_model._hip_half_width(rest, heads)))
        output = body_model._model(pose.float(), parameters)
        transforms = output["bone_poses"] @ torch.linalg.inv(output["rest_bone_poses"])
        ours = body_model._keypoints(weights, transforms)
        full = anny.Anny(phenotypes="all", phenotype_blendshapes="original", skinning_method="lbs")
        reference = KeypointsRegressor.coco(full, labels=list(COCO_KEYPOINTS))(full(pose, parameters.double()))
    np.testing.assert_allclose(ours.numpy(), reference.numpy(), atol=5e-4)


def test_pose_output_shapes_types_and_values(body_model) -> None:
    people = varied_people(5, seed=7)
    posed = body_model.pose(people, [sample_gait(np.random.default_rng(k)) for k in range(5)])
    assert isinstance(posed, PosedBodies)
    assert posed.vertices.shape == (5, body_model.vertex_count, 3) and posed.vertices.dtype == np.float32
    assert posed.keypoints.shape == (5, len(COCO_KEYPOINTS), 3) and posed.keypoints.dtype == np.float32
    assert posed.stature_m.shape == (5,)
    assert np.isfinite(posed.vertices).all() and np.isfinite(posed.keypoints).all()
    # Different people, different bodies; and a body does not depend on the batch it is posed in.
    assert min(np.abs(posed.vertices[a] - posed.vertices[b]).max() for a in range(5) for b in range(a)) > 0.01
    alone = body_model.pose(people[2:3], [sample_gait(np.random.default_rng(2))])
    np.testing.assert_allclose(alone.vertices[0], posed.vertices[2], atol=1e-4)
    empty = body_model.pose([], [])
    assert empty.vertices.shape == (0, body_model.vertex_count, 3) and empty.keypoints.shape == (0, 17, 3)
    with pytest.raises(ValueError, match="gaits"):
        body_model.pose(people, [WALK])


def test_gender_runs_from_female_to_male(body_model) -> None:
    posed = body_model.pose([person(gender=0.0), person(gender=1.0)], [STAND, STAND])
    shoulders = np.abs(posed.keypoints[:, K["left_shoulder"], 1] - posed.keypoints[:, K["right_shoulder"], 1])
    assert shoulders[1] > shoulders[0] + 0.02  # same stature, broader male shoulders


def test_mesh_and_body_parts(body_model) -> None:
    faces, parts = body_model.faces, body_model.vertex_parts
    assert faces.dtype == np.int32 and faces.ndim == 2 and faces.shape[1] == 3
    assert faces.min() == 0 and faces.max() == body_model.vertex_count - 1
    assert parts.dtype == np.uint8 and parts.shape == (body_model.vertex_count,)
    assert set(np.unique(parts)) == set(range(len(BODY_PARTS)))
    # One closed surface facing outwards (Mitsuba's diffuse BSDF is one-sided): no eyes or mouth inside.
    vertices = body_model.pose([person()], [Gait(0.0, 0.0, 0.0)]).vertices[0]
    mesh = trimesh.Trimesh(vertices, faces, process=False)
    assert mesh.is_watertight and mesh.body_count == 1
    assert 0.05 < mesh.volume < 0.12  # m^3, an average 1.75 m person
    # Each part where it belongs on a person standing.
    height = {name: np.median(vertices[parts == index, 2]) for index, name in enumerate(BODY_PARTS)}
    assert height["hair"] > 1.6 and height["shoes"] < 0.1
    assert height["hair"] > height["upper"] > height["lower"] > height["shins"] > height["shoes"]
    assert height["upper"] > height["forearms"] > height["lower"]


def test_sampling_is_deterministic_and_within_range() -> None:
    def draw(seed: int) -> tuple[list[Phenotype], list[Gait]]:
        rng = np.random.default_rng(seed)
        return [sample_phenotype(rng, (1.6, 1.8)) for _ in range(400)], [sample_gait(rng) for _ in range(2000)]

    phenotypes, gaits = draw(1)
    assert draw(1) == (phenotypes, gaits)
    assert draw(2) != (phenotypes, gaits)
    assert all(1.6 <= p.height_m <= 1.8 and 18.0 <= p.age_years <= 80.0 for p in phenotypes)
    assert all(abs(sum(p.ethnicity) - 1.0) < 1e-9 and min(p.ethnicity) >= 0.0 for p in phenotypes)
    assert all(0.0 <= value <= 1.0 for p in phenotypes for value in (p.gender, p.weight, p.muscle, p.proportions))
    genders = np.array([p.gender for p in phenotypes])
    assert 0.4 < np.mean(genders > 0.5) < 0.6 and np.mean(np.abs(genders - 0.5) > 0.25) > 0.9
    speeds = np.array([g.speed_mps for g in gaits])
    assert abs(np.mean(speeds == 0.0) - 0.20) < 0.03
    assert abs(np.mean((speeds > 0.0) & (speeds < 2.0)) - 0.65) < 0.03
    assert abs(np.mean(speeds >= 2.5) - 0.15) < 0.03
    assert all(0.0 <= g.phase < 1.0 and 0.0 <= g.arm_swing <= 1.5 for g in gaits)
    assert phenotypes[0].to_dict()["height_m"] == round(phenotypes[0].height_m, 4)
    assert set(gaits[0].to_dict()) == {"speed_mps", "phase", "arm_swing"}


def test_the_decoders_upright_keypoint_prior_is_where_sampled_walkers_have_their_keypoints(body_model) -> None:
    """The decoder places each keypoint, and the box's top and bottom, by :data:`UPRIGHT_OFFSETS` and
    :data:`LOWER_ANKLE_OFFSET`: they must be the rendered people's own, dressed as they are rendered (seen level, in
    heights below the middle of the body's vertical extent), or every box comes out short (it did, by 6 %, with
    anatomical guesses, and by 2 % once people wore hair and soles)."""
    rng = np.random.default_rng(7)
    people = [sample_phenotype(rng) for _ in range(96)]
    posed = body_model.pose(people, [sample_gait(rng) for _ in people])
    dressed = [dress(posed.vertices[k], posed.keypoints[k], body_model.faces,
                     vertex_thickness(body_model.vertex_parts, sample_appearance(rng, people[k])))
               for k in range(len(people))]
    top = np.array([vertices[:, 2].max() for vertices, _ in dressed])  # soles on z = 0
    offsets = 0.5 - np.array([keypoints[:, 2] for _, keypoints in dressed]) / top[:, None]
    np.testing.assert_allclose(np.median(offsets, axis=0), UPRIGHT_OFFSETS, atol=0.02)
    assert np.median(offsets[:, [K["left_ankle"], K["right_ankle"]]].max(axis=1)) == pytest.approx(
        LOWER_ANKLE_OFFSET, abs=0.015)


def test_the_trackers_face_placement_is_where_sampled_walkers_have_their_nose_and_eyes(body_model) -> None:
    """The tracker turns a walker's face by :data:`FACE_AHEAD_OF_EARS` (nose and eyes ahead of the ears' midpoint,
    in heights): the rendered people's own, or a profile's nose lands off the face it is drawn on."""
    rng = np.random.default_rng(11)
    people = [sample_phenotype(rng) for _ in range(48)]
    posed = body_model.pose(people, [sample_gait(rng) for _ in people])
    top = posed.vertices[..., 2].max(axis=1)
    ears = 0.5 * (posed.keypoints[:, K["left_ear"], 0] + posed.keypoints[:, K["right_ear"], 0])  # bodies face +x
    nose = (posed.keypoints[:, K["nose"], 0] - ears) / top
    eyes = (0.5 * (posed.keypoints[:, K["left_eye"], 0] + posed.keypoints[:, K["right_eye"], 0]) - ears) / top
    assert np.median(nose) == pytest.approx(FACE_AHEAD_OF_EARS["nose"], abs=0.004)
    assert np.median(eyes) == pytest.approx(FACE_AHEAD_OF_EARS["eyes"], abs=0.004)
