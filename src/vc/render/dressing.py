"""Clothes, hair and shoes as volume: each body part's surface moved out along its normals by what covers it.

A bare anny body is the skin. Real passers-by stand taller and wider than their skin: hair or a hood over the
scalp, a coat over the torso, soles under the feet. A detector trained on bare bodies learns where the joints lie
from the silhouette of the skin — on a real person in a hat, a parka and shoes it puts the face too high and
the ankles too low. Rendered dressed, the skeleton sits inside a clothed outline as on real people
(docs/decisions/0005-dressed-people.md).

Every vertex moves out along its area-weighted normal by its part's thickness (``Appearance.part_thickness_m``),
then the dressed person is stood on its soles (the lowest point back on z = 0; the joints, which clothes do
not move, lifted with it). An offset surface is the simplest cloth model there is — no folds, no hems, no
garment longer than the part under it — but at 1-2 cm a pixel what a detector sees of clothing is its outline,
and that it gets right. Parts overlap where limbs touch the torso; the renderer draws the union.
"""

from __future__ import annotations

import numpy as np


def vertex_normals(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """(V, 3) unit outward normals of a closed mesh: the sum of the normals of the faces around each vertex,
    each weighted by its area (the cross product's length), so small slivers do not swing it."""
    corners = vertices[faces]  # (F, 3, 3)
    face_normals = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    normals = np.zeros_like(vertices)
    for corner in range(3):
        np.add.at(normals, faces[:, corner], face_normals)
    length = np.linalg.norm(normals, axis=1, keepdims=True)
    return normals / np.maximum(length, 1e-12)


def dress(vertices: np.ndarray, keypoints: np.ndarray, faces: np.ndarray, vertex_thickness_m: np.ndarray
          ) -> tuple[np.ndarray, np.ndarray]:
    """A posed body in its body frame (z up, soles on z = 0) dressed: (vertices (V, 3), keypoints (K, 3)).

    ``vertex_thickness_m`` (V,) is how far each vertex's surface lies outside the skin. The dressed person
    stands on whatever is lowest (a shoe's sole): everything is lifted by how far that went below z = 0.
    """
    thickness = np.asarray(vertex_thickness_m, dtype=np.float64)[:, None]
    dressed = vertices.astype(np.float64) + thickness * vertex_normals(vertices.astype(np.float64), faces)
    lift = -float(dressed[:, 2].min())
    dressed[:, 2] += lift
    lifted = keypoints.astype(np.float64).copy()
    lifted[:, 2] += lift
    return dressed.astype(vertices.dtype), lifted.astype(keypoints.dtype)
