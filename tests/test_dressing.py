"""Clothes as volume: surfaces move out along their normals by their part's thickness, and the person stands on
their soles."""

from __future__ import annotations

import numpy as np
import pytest
import trimesh

from vc.render.appearance import WARDROBES, Appearance, vertex_thickness
from vc.render.bodies import BODY_PARTS, Gait, sample_phenotype
from vc.render.dressing import dress, vertex_normals

pytestmark = pytest.mark.xdist_group("anny")


def test_a_sphere_dressed_grows_by_the_thickness_and_stays_on_the_floor() -> None:
    sphere = trimesh.creation.icosphere(subdivisions=3, radius=0.5)
    vertices = np.asarray(sphere.vertices) + [0.0, 0.0, 0.5]  # resting on z = 0
    faces = np.asarray(sphere.faces)
    normals = vertex_normals(vertices, faces)
    np.testing.assert_allclose(np.linalg.norm(normals, axis=1), 1.0, atol=1e-9)
    assert np.all(np.einsum("ij,ij->i", normals, vertices - [0.0, 0.0, 0.5]) > 0)  # outward
    joint = np.array([[0.0, 0.0, 0.5]])
    dressed, lifted = dress(vertices, joint, faces, np.full(len(vertices), 0.02))
    radii = np.linalg.norm(dressed - lifted[0], axis=1)
    np.testing.assert_allclose(radii, 0.52, atol=2e-3)
    assert dressed[:, 2].min() == pytest.approx(0.0, abs=1e-12)
    assert lifted[0, 2] == pytest.approx(0.52, abs=1e-9)  # the joint rises with the sole under it


def test_nothing_moves_where_nothing_is_worn() -> None:
    sphere = trimesh.creation.icosphere(subdivisions=2)
    vertices = np.asarray(sphere.vertices) + [0.0, 0.0, 1.0]
    dressed, lifted = dress(vertices, vertices[:3], np.asarray(sphere.faces), np.zeros(len(vertices)))
    np.testing.assert_allclose(dressed, vertices, atol=1e-12)
    np.testing.assert_allclose(lifted, vertices[:3], atol=1e-12)


def _posed_body(body_model, thickness: dict[str, float]):
    rng = np.random.default_rng(3)
    posed = body_model.pose([sample_phenotype(rng)], [Gait(speed_mps=0.0, phase=0.2, arm_swing=0.3)])
    appearance = Appearance({part: (0.5, 0.5, 0.5) for part in BODY_PARTS},
                            {part: thickness.get(part, 0.0) for part in BODY_PARTS})
    dressed, joints = dress(posed.vertices[0], posed.keypoints[0], body_model.faces,
                            vertex_thickness(body_model.vertex_parts, appearance))
    return posed.vertices[0], posed.keypoints[0], dressed, joints


def test_shoes_lift_the_body_by_their_sole_and_hair_adds_to_the_top_of_the_head(body_model) -> None:
    bare, joints, dressed, lifted = _posed_body(body_model, {"shoes": 0.025, "hair": 0.02})
    lift = lifted[:, 2] - joints[:, 2]
    np.testing.assert_allclose(lift, lift[0], atol=1e-6)  # the skeleton moves as one
    assert 0.018 < lift[0] <= 0.0251  # the sole, give or take its slope under a standing foot
    assert dressed[:, 2].min() == pytest.approx(0.0, abs=1e-6)
    top_gain = dressed[:, 2].max() - bare[:, 2].max()
    assert 0.03 < top_gain < 0.047  # the sole's lift plus most of the hair's 2 cm on the crown
    skin = np.flatnonzero(body_model.vertex_parts == BODY_PARTS.index("skin"))
    np.testing.assert_allclose(dressed[skin] - bare[skin], np.broadcast_to([0.0, 0.0, lift[0]], (len(skin), 3)),
                               atol=1e-5)  # skin (face, hands) is not covered


def test_a_coat_widens_the_torso(body_model) -> None:
    bare, _, dressed, _ = _posed_body(body_model, {"upper": 0.03})
    upper = body_model.vertex_parts == BODY_PARTS.index("upper")
    widening = np.ptp(dressed[upper][:, 1]) - np.ptp(bare[upper][:, 1])  # shoulder to shoulder: the body frame's y
    assert 0.05 < widening < 0.065


def test_wardrobes_dress_winter_thicker_than_summer() -> None:
    assert WARDROBES["winter"].upper_thickness_m[0] > WARDROBES["summer"].upper_thickness_m[1]
