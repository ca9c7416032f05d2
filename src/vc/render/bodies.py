"""Synthetic people: anny bodies with a sampled phenotype, posed by a procedural gait, in a body frame.

The body frame is what the renderer places in the scene: metres, z up, the lowest point of the body on z = 0,
the person facing +x (so their left is +y) and the pelvis (anny's root joint) on the z axis.

Topology. anny's own mesh has 13.7k vertices and 27k triangles, far more than a person 100-200 px tall needs:
one pixel is 9-18 mm there, while anny's decimated ``notoes_collapse10pc`` topology (1229 vertices, 2454
triangles, one closed surface without eyes, tongue or mouth cavity) has 95 % of the full mesh's vertices within
3.5 mm of it (1.4 mm on average; the tip of the nose and the toes are flattened by 1-2 cm). Mitsuba rebuilds
its acceleration structure for every body of every sample, and the forward pass is 2-3 times faster.

Keypoints. The retopology drops the link to anny's base mesh that ``anny.keypoints.KeypointsRegressor`` needs,
so the COCO regressor is evaluated on the full-resolution body without building it: a keypoint is a fixed
average of full-mesh vertices, each skinned by linear blend skinning, so it equals
``sum_j T_j (sum_v r_v w_vj x_v)`` where ``T_j`` are the bone transforms (the rig is shared by both topologies),
``r_v`` the regressor, ``w_vj`` the skinning weights and ``x_v`` the rest vertices, affine in anny's phenotype
blendshape coefficients. The inner sums are precomputed once per (keypoint, bone) pair, so the keypoints are
exactly anny's COCO regressor applied to the full-resolution posed body, for the cost of a few small products.

Anny conventions this module converts from: anny's rest frame has z up, metres, the root joint at the origin,
the person facing -y with their left on +x; the rest pose is an A-pose with elbows bent forward; its gender
parameter runs from 0 = male to 1 = female (the opposite of :class:`Phenotype`'s).
"""

from __future__ import annotations

from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from dataclasses import asdict, dataclass

import anny
import numpy as np
import torch
from anny.keypoints import KeypointsRegressor
from anny.models.phenotype import phenotype_blendshape_weights

from vc.keypoints import COCO_KEYPOINTS

#: Labels of :attr:`BodyModel.vertex_parts`. ``forearms`` (elbow to wrist) and ``shins`` (knee to ankle) are
#: the skin that short sleeves and shorts or skirts leave bare: the appearance colours them as skin or as the
#: garment above them. Hands, face, ears and neck are ``skin``; ``hair`` is the scalp (top and back of the
#: head above the ears and the nape); ``upper`` is torso and upper arms, ``lower`` pelvis and thighs,
#: ``shoes`` the feet.
BODY_PARTS: tuple[str, ...] = ("skin", "hair", "upper", "lower", "shoes", "forearms", "shins")

#: The anny topology rendered (see the module docstring).
TOPOLOGY = "notoes_collapse10pc"

#: Age in years -> anny's age parameter: anny's own calibration of its bodies' stature against WHO growth data
#: (``anny/data/shape_calibration``, ``anny.shape_distribution.MorphologicalAgeMapping``). Adults span little
#: of the parameter: 18 years is 0.77, 64 years 0.83 (its "young" and "old" blendshapes are at 2/3 and 1).
AGE_YEARS = (0.0, 1.0, 4.0, 11.0, 16.0, 18.0, 64.0, 110.0)
AGE_PARAMETER = (0.0, 0.05, 0.215, 0.415, 0.67, 0.77, 0.83, 1.0)


@dataclass(frozen=True)
class Phenotype:
    """Who a synthetic person is: the anny shape parameters, with age and stature in physical units."""

    gender: float  # 0 = female .. 1 = male
    age_years: float
    height_m: float  # standing stature in the rest pose, top of the head to the soles
    weight: float  # anny parameters in [0, 1]
    muscle: float
    proportions: float
    ethnicity: tuple[float, float, float]  # (african, asian, caucasian) mixture weights, summing to 1

    def to_dict(self) -> dict:
        return {"gender": round(self.gender, 3), "age_years": round(self.age_years, 1),
                "height_m": round(self.height_m, 4), "weight": round(self.weight, 3),
                "muscle": round(self.muscle, 3), "proportions": round(self.proportions, 3),
                "ethnicity": [round(w, 3) for w in self.ethnicity]}


@dataclass(frozen=True)
class Gait:
    """How a person moves: a point of a walk/run cycle, or a relaxed standing pose when ``speed_mps`` is 0.

    Standing people use ``phase`` for which leg carries the weight and how far the feet are staggered, and
    ``arm_swing`` for how far the arms hang off the vertical, so the three numbers describe every pose.
    """

    speed_mps: float  # 0 = standing, about 1.0-1.8 walking, 2.5-4 running
    phase: float  # [0, 1): left heel strike at 0 (left leg forward), right heel strike at 0.5
    arm_swing: float  # [0, 1.5] scale of the arm swing

    def to_dict(self) -> dict:
        return {key: round(value, 3) for key, value in asdict(self).items()}


def sample_phenotype(rng: np.random.Generator, height_range_m: tuple[float, float] = (1.5, 1.95)) -> Phenotype:
    """An adult passer-by. The stature is uniform over the scene's prior range (the range is the prior);
    sex is 50/50 with anny's continuous gender kept near its ends; ages 18-80, mostly of working age (mode
    about 35); build parameters spread over their range; ethnicity a Dirichlet mixture that is often near-pure.
    """
    low, high = height_range_m
    if not 0.0 < low <= high:
        raise ValueError(f"height range must satisfy 0 < low <= high, got {height_range_m}")
    femininity = float(rng.beta(1.2, 10.0))
    gender = femininity if rng.random() < 0.5 else 1.0 - femininity
    mix = rng.dirichlet((0.5, 0.5, 0.5))
    return Phenotype(gender=1.0 - gender, age_years=float(18.0 + 62.0 * rng.beta(1.8, 3.2)),
                     height_m=float(rng.uniform(low, high)), weight=float(rng.beta(2.5, 2.5)),
                     muscle=float(rng.beta(2.5, 2.5)), proportions=float(rng.beta(2.0, 2.0)),
                     ethnicity=(float(mix[0]), float(mix[1]), float(mix[2])))


def sample_gait(rng: np.random.Generator) -> Gait:
    """20 % standing, 65 % walking (preferred speeds around 1.35 m/s), 15 % running (2.5-4 m/s)."""
    kind = rng.random()
    phase = float(rng.random())
    if kind < 0.20:
        return Gait(speed_mps=0.0, phase=phase, arm_swing=float(rng.uniform(0.0, 1.0)))
    if kind < 0.85:
        speed = float(np.clip(rng.normal(1.35, 0.2), 0.9, 1.9))
        return Gait(speed_mps=speed, phase=phase, arm_swing=float(rng.uniform(0.3, 1.5)))
    return Gait(speed_mps=float(rng.uniform(2.5, 4.0)), phase=phase, arm_swing=float(rng.uniform(0.7, 1.5)))


@dataclass(frozen=True)
class PosedBodies:
    """A batch of posed bodies in the body frame (see the module docstring)."""

    vertices: np.ndarray  # (B, V, 3) float32
    keypoints: np.ndarray  # (B, 17, 3) float32, COCO order
    stature_m: np.ndarray  # (B,) rest-pose stature achieved


# Sagittal joint angles (degrees) over one gait cycle of a leg, starting at its heel strike, at ten evenly
# spaced points; after Winter, "Biomechanics and Motor Control of Human Movement" (normal walking at about
# 1.4 m/s) and Novacheck, "The biomechanics of running", Gait & Posture 7 (1998) (running at about 3.5 m/s).
# Hip: flexion +; knee: flexion +; ankle: dorsiflexion +.
_WALK = {"hip": (30, 27, 18, 8, -2, -9, -5, 12, 27, 33),
         "knee": (5, 18, 15, 7, 5, 12, 38, 60, 45, 15),
         "ankle": (0, -5, 5, 9, 10, 3, -15, -8, 0, 1)}
_RUN = {"hip": (35, 25, 10, -5, -10, 0, 25, 45, 55, 48),
        "knee": (20, 40, 35, 25, 30, 65, 95, 100, 75, 35),
        "ankle": (5, 18, 15, 0, -20, -15, -5, 0, 5, 8)}


def _cycle(values: Sequence[float], phase: np.ndarray) -> np.ndarray:
    """Periodic Catmull-Rom interpolation of evenly spaced samples of one cycle, at ``phase`` in [0, 1)."""
    table = np.asarray(values, dtype=np.float64)
    n = len(table)
    position = np.mod(phase, 1.0) * n
    i = np.floor(position).astype(int)
    t = position - i
    p0, p1, p2, p3 = (table[(i + k) % n] for k in (-1, 0, 1, 2))
    return 0.5 * (2 * p1 + (p2 - p0) * t + (2 * p0 - 5 * p1 + 4 * p2 - p3) * t**2 + (3 * p1 - p0 - 3 * p2 + p3) * t**3)


def _axis_angle(axis: np.ndarray, angle: np.ndarray) -> np.ndarray:
    """Rotation matrices (..., 3, 3) about unit ``axis`` (..., 3) by ``angle`` (...) radians (Rodrigues)."""
    axis = np.broadcast_to(axis, (*np.shape(angle), 3))
    x, y, z = axis[..., 0], axis[..., 1], axis[..., 2]
    c, s = np.cos(angle), np.sin(angle)
    C = 1.0 - c
    return np.stack([np.stack([c + x * x * C, x * y * C - z * s, x * z * C + y * s], -1),
                     np.stack([y * x * C + z * s, c + y * y * C, y * z * C - x * s], -1),
                     np.stack([z * x * C - y * s, z * y * C + x * s, c + z * z * C], -1)], -2)


def _rotation_between(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """The smallest rotations (..., 3, 3) taking unit vectors ``a`` to ``b`` (never antiparallel here)."""
    axis = np.cross(a, b)
    sine = np.linalg.norm(axis, axis=-1)
    angle = np.arctan2(sine, np.sum(a * b, axis=-1))
    axis = axis / np.maximum(sine, 1e-12)[..., None]
    return _axis_angle(axis, angle)


_X, _Y, _Z = np.eye(3)


class BodyModel:
    """anny bodies posed in batches. Build once per process: it loads anny's model data (the first build ever
    takes about a minute and writes anny's cache, see ``ANNY_CACHE_DIR``), then every :meth:`pose` is one
    batched forward pass.
    """

    def __init__(self) -> None:
        full = anny.Anny(phenotypes="all", phenotype_blendshapes="original", skinning_method="lbs")
        model = anny.Anny(topology=TOPOLOGY, phenotypes="all", skinning_method="lbs")
        if model.bone_labels != full.bone_labels or not torch.equal(
                model.stacked_phenotype_blend_shapes_mask, full.stacked_phenotype_blend_shapes_mask):
            raise RuntimeError(f"anny's {TOPOLOGY!r} body does not share the full body's rig and phenotype blendshapes")
        regressor = KeypointsRegressor.coco(full, labels=list(COCO_KEYPOINTS)).regression_weights
        self._keypoints = _FullBodyKeypoints(full, regressor)
        template_keypoints = (regressor @ full.template_vertices).numpy()
        del full

        self.faces: np.ndarray = model.faces.numpy().astype(np.int32)
        self.vertex_count: int = int(model.template_vertices.shape[0])
        stems = _dominant_bone_stems(model)
        self.vertex_parts: np.ndarray = _vertex_parts(model, stems, template_keypoints)
        self._trunk = torch.from_numpy(np.flatnonzero(np.isin(stems, ("root", "pelvis", "spine", "upperleg"))))
        self._labels = list(model.phenotype_labels)
        self._bone = {label: index for index, label in enumerate(model.bone_labels)}
        self._model = model.to(dtype=torch.float32)

    def pose(self, phenotypes: Sequence[Phenotype], gaits: Sequence[Gait]) -> PosedBodies:
        """Shape, pose and place a batch of people in their body frames, in one anny forward pass."""
        if len(phenotypes) != len(gaits):
            raise ValueError(f"got {len(phenotypes)} phenotypes but {len(gaits)} gaits")
        if not phenotypes:
            return PosedBodies(np.zeros((0, self.vertex_count, 3), np.float32),
                               np.zeros((0, len(COCO_KEYPOINTS), 3), np.float32), np.zeros(0, np.float32))
        with torch.inference_mode(), _single_thread():
            parameters, weights, rest, scale, stature = self._shape(phenotypes)
            heads = self._rest_bone_heads(weights)
            pose = self._pose_parameters(gaits, heads, self._hip_half_width(rest, heads))
            output = self._model(torch.from_numpy(pose).to(torch.float32), parameters)
            transforms = output["bone_poses"] @ torch.linalg.inv(output["rest_bone_poses"])
            root = output["bone_poses"][:, 0, :3, 3]
            vertices = _to_body_frame(output["vertices"], root, scale)
            keypoints = _to_body_frame(self._keypoints(weights, transforms), root, scale)
            floor = vertices[..., 2].amin(1)[:, None]
            vertices[..., 2] -= floor
            keypoints[..., 2] -= floor
        return PosedBodies(vertices.numpy(), keypoints.numpy(), stature.numpy())

    def _shape(self, phenotypes: Sequence[Phenotype]) -> tuple[torch.Tensor, ...]:
        """anny's phenotype parameters (B, labels), their phenotype blendshape weights (B, C), the rest vertices
        (B, V, 3) in anny's frame, and the scale and the stature (B,) that reach each requested stature.

        anny's height parameter is set so that its body comes closest to the requested stature (it spans about
        1.35-2.4 m for adults, so normally exactly), then a uniform scale absorbs the rest: heights are reached
        with anny's own height-dependent proportions, never by scaling a body of another height. Rest vertices
        are affine in the height parameter, so two evaluations (heights 0 and 1) locate it.
        """
        rows = []
        for p in phenotypes:
            african, asian, caucasian = p.ethnicity
            values = {"gender": 1.0 - p.gender, "age": float(np.interp(p.age_years, AGE_YEARS, AGE_PARAMETER)),
                      "muscle": p.muscle, "weight": p.weight, "height": 0.0, "proportions": p.proportions,
                      "cupsize": 0.5, "firmness": 0.5, "african": african, "asian": asian, "caucasian": caucasian}
            rows.append([values[label] for label in self._labels])
        parameters = torch.tensor(rows, dtype=torch.float32)
        target = torch.tensor([p.height_m for p in phenotypes], dtype=torch.float32)
        height = self._labels.index("height")
        ends = parameters.repeat(2, 1)
        ends[len(phenotypes):, height] = 1.0
        low_weights, high_weights = self._blendshape_weights(ends).chunk(2)
        low_rest, high_rest = self._model.get_rest_vertices(
            torch.cat([low_weights, high_weights]) @ self._model.phenotype_blendshape_projection).chunk(2)
        low, high = _stature(low_rest), _stature(high_rest)
        t = ((target - low) / (high - low)).clamp(0.0, 1.0)
        parameters[:, height] = t
        rest = low_rest + t[:, None, None] * (high_rest - low_rest)
        achieved = _stature(rest)
        scale = target / achieved
        return parameters, low_weights + t[:, None] * (high_weights - low_weights), rest, scale, achieved * scale

    def _blendshape_weights(self, parameters: torch.Tensor) -> torch.Tensor:
        """anny's phenotype blendshape weights before its compaction: the same for both topologies."""
        model = self._model
        return phenotype_blendshape_weights(parameters, self._labels, model.anchors,
                                            model.stacked_phenotype_blend_shapes_mask,
                                            extrapolate=model.extrapolate_phenotypes)

    def _rest_bone_heads(self, weights: torch.Tensor) -> np.ndarray:
        model = self._model
        coefficients = weights @ model.phenotype_blendshape_projection
        heads = model.template_bone_heads + torch.einsum("bc,cjd->bjd", coefficients, model.bone_heads_blendshapes)
        return heads.double().numpy()

    def _hip_half_width(self, rest: torch.Tensor, heads: np.ndarray) -> np.ndarray:
        """How far (B,) the hips and thighs reach sideways where the hands hang, in anny's rest frame."""
        shoulder = heads[:, self._bone["upperarm01.L"]]
        reach = np.linalg.norm(heads[:, self._bone["wrist.L"]] - shoulder, axis=-1)
        trunk = rest[:, self._trunk].double().numpy()
        band = (trunk[..., 2] > (shoulder[:, 2] - reach - 0.05)[:, None]) & (
            trunk[..., 2] < (shoulder[:, 2] - 0.6 * reach)[:, None])
        return np.where(band, np.abs(trunk[..., 0]), 0.0).max(1)

    def _pose_parameters(self, gaits: Sequence[Gait], rest_heads: np.ndarray, hip_half_width: np.ndarray
                         ) -> np.ndarray:
        """anny ``local-ref`` pose parameters (B, bones, 4, 4) of each gait, for bodies with these rest bone
        heads (B, bones, 3) and hips (see :meth:`_hip_half_width`).

        In ``local-ref``, a bone's delta is a rotation about its head in anny's rest-frame axes (x = the
        person's left, y = backwards, z = up), applied before its parent's, so joint angles compose down the
        chain: hip, knee and ankle flex about x; the arms are first brought down from anny's A-pose to hang
        beside the body, then swing about x; the elbow bends about its own rest axis.
        """
        count = len(gaits)
        speed = np.array([g.speed_mps for g in gaits])
        phase = np.array([g.phase for g in gaits])
        swing = np.array([g.arm_swing for g in gaits])

        # Walking amplitude grows with speed; standing keeps a fifth of it: a staggered, relaxed stance.
        walk = np.clip(speed / 1.35, 0.2, 1.3)
        x = np.clip((speed - 1.9) / 0.6, 0.0, 1.0)
        run = x * x * (3.0 - 2.0 * x)  # smoothstep from walking to running between 1.9 and 2.5 m/s
        run_amp = np.clip(0.85 + 0.1 * (speed - 2.5), 0.85, 1.1)

        pose = np.tile(np.eye(4), (count, len(self._bone), 1, 1))

        def rotate(bone: str, rotation: np.ndarray) -> None:
            index = self._bone[bone]
            pose[:, index, :3, :3] = rotation @ pose[:, index, :3, :3]

        # Yaw: the pelvis turns with the forward leg, the shoulders the other way, the head keeps looking ahead.
        cos = np.cos(2 * np.pi * phase)
        pelvis = np.radians(-(4.0 * walk * (1 - run) + 6.0 * run) * cos)
        thorax = np.radians((5.0 * walk * (1 - run) + 8.0 * run) * cos)
        rotate("root", _axis_angle(_Z, pelvis))
        rotate("spine03", _axis_angle(_Z, thorax - pelvis))
        lean = np.radians(2.0 * (1 - run) + (6.0 + 2.0 * (speed - 2.5)) * run)
        rotate("spine05", _axis_angle(_X, lean))
        rotate("neck01", _axis_angle(_Z, -thorax) @ _axis_angle(_X, -0.7 * lean))

        step_width = np.interp(speed, [0.0, 0.5, 2.0, 3.0], [0.22, 0.12, 0.10, 0.07])
        for side, sign, offset in (("L", 1.0, 0.0), ("R", -1.0, 0.5)):
            t = phase + offset
            angles = {joint: np.radians((1 - run) * walk * _cycle(_WALK[joint], t) + run * run_amp
                                        * _cycle(_RUN[joint], t)) for joint in _WALK}
            hip = rest_heads[:, self._bone[f"upperleg01.{side}"]]
            ankle = rest_heads[:, self._bone[f"foot.{side}"]]
            length = hip[:, 2] - ankle[:, 2]
            adduction = np.arctan2(ankle[:, 0] - hip[:, 0], length) - np.arctan2(
                sign * step_width / 2 - hip[:, 0], length)
            rotate(f"upperleg01.{side}", _axis_angle(_X, -angles["hip"]) @ _axis_angle(_Y, adduction))
            rotate(f"lowerleg01.{side}", _axis_angle(_X, angles["knee"]))
            rotate(f"foot.{side}", _axis_angle(_X, -angles["ankle"]))

            # Arms: opposite to the leg of the same side; more swing and elbow bend when running.
            amplitude = swing * (18.0 * walk * (1 - run) + 35.0 * run)
            flexion = np.radians(-amplitude * np.cos(2 * np.pi * t) - 4.0 * (1 - run) + 8.0 * run)
            elbow = np.radians(12.0 + 6.0 * walk * (1 - run) + 70.0 * run + 0.3 * np.degrees(np.maximum(flexion, 0)))
            shoulder = rest_heads[:, self._bone[f"upperarm01.{side}"]]
            elbow_head = rest_heads[:, self._bone[f"lowerarm01.{side}"]]
            wrist = rest_heads[:, self._bone[f"wrist.{side}"]]
            upper = _unit(elbow_head - shoulder)
            fore = _unit(wrist - elbow_head)
            # Abducted just enough for the wrists to pass 4.5 cm outside the hips: hands beside, not in, the body.
            clearance = (hip_half_width + 0.045 - sign * shoulder[:, 0]) / np.linalg.norm(wrist - shoulder, axis=-1)
            abduction = np.arcsin(np.clip(clearance, np.sin(np.radians(3.0)), np.sin(np.radians(30.0))))
            hanging = np.stack([sign * np.sin(abduction), np.zeros(count), -np.cos(abduction)], -1)
            rotate(f"upperarm01.{side}", _axis_angle(_X, -flexion) @ _rotation_between(upper, hanging))
            rest_elbow = np.arccos(np.clip(np.sum(upper * fore, -1), -1.0, 1.0))
            rotate(f"lowerarm01.{side}", _axis_angle(_unit(np.cross(upper, fore)), elbow - rest_elbow))
        return pose


class _FullBodyKeypoints:
    """anny's COCO keypoints of the full-resolution body, from the bone transforms shared by both topologies.

    With ``r`` the regressor, ``w`` the skinning weights and ``x(c)`` the rest vertices (affine in the phenotype
    blendshape weights ``c``), keypoint ``k`` is ``sum_j T_j m_kj(c)`` with the affine points
    ``m_kj(c) = sum_v r_kv w_vj [x_v(c), 1]``, precomputed for the few (keypoint, bone) pairs with weight.
    """

    def __init__(self, full: anny.Anny, regressor: torch.Tensor) -> None:
        weights = torch.zeros(full.template_vertices.shape[0], full.bone_count, dtype=regressor.dtype)
        weights.scatter_add_(1, full.vertex_bone_indices, full.vertex_bone_weights)
        support = torch.nonzero(regressor.sum(0) > 0)[:, 0]
        mix = regressor[:, support, None] * weights[None, support, :]  # r_kv w_vj over the regressor's support
        pair_weight = mix.sum(1)
        keypoint, self.bone = torch.nonzero(pair_weight > 1e-9, as_tuple=True)
        pair_mix = mix[keypoint, :, self.bone]  # (P, S)
        self.rest = (pair_mix @ full.template_vertices[support]).float()  # (P, 3)
        self.shapes = torch.einsum("ps,csd->cpd", pair_mix, full.blendshapes[:, support]).float()  # (C, P, 3)
        self.weight = pair_weight[keypoint, self.bone].float()  # (P,)
        self.gather = torch.zeros(len(COCO_KEYPOINTS), len(keypoint))
        self.gather[keypoint, torch.arange(len(keypoint))] = 1.0

    def __call__(self, weights: torch.Tensor, transforms: torch.Tensor) -> torch.Tensor:
        """(B, 17, 3) keypoints in anny's frame, from blendshape weights (B, C) and bone transforms (B, J, 4, 4)."""
        rest = self.rest + torch.einsum("bc,cpd->bpd", weights, self.shapes)
        pair_transforms = transforms[:, self.bone]
        posed = torch.einsum("bpij,bpj->bpi", pair_transforms[..., :3, :3], rest)
        posed = posed + self.weight[None, :, None] * pair_transforms[..., :3, 3]
        return torch.einsum("kp,bpd->bkd", self.gather, posed)


@contextmanager
def _single_thread() -> Iterator[None]:
    """Run torch on one thread: at these sizes a second thread gains under 10 %, and when the cores are busy
    (Mitsuba, other workers) OpenMP's barriers stall a 2-thread forward pass for hundreds of milliseconds."""
    previous = torch.get_num_threads()
    torch.set_num_threads(1)
    try:
        yield
    finally:
        torch.set_num_threads(previous)


def _unit(v: np.ndarray) -> np.ndarray:
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


def _stature(vertices: torch.Tensor) -> torch.Tensor:
    """Top of the head to the soles of (B, V, 3) rest vertices, z up."""
    return vertices[..., 2].amax(1) - vertices[..., 2].amin(1)


#: anny's frame (left = +x, facing -y) -> body frame (facing +x, left = +y): a quarter turn about z.
_ANNY_TO_BODY = torch.tensor([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])


def _to_body_frame(points: torch.Tensor, root: torch.Tensor, scale: torch.Tensor) -> torch.Tensor:
    """(B, N, 3) anny points -> scaled body frame with the root joint on the z axis (z not yet grounded)."""
    centred = points - torch.nn.functional.pad(root[:, :2], (0, 1))[:, None, :]
    return scale[:, None, None] * centred @ _ANNY_TO_BODY.T


def _dominant_bone_stems(model: anny.Anny) -> np.ndarray:
    """The bone that moves each vertex most, without side or index: "upperarm", "spine", "finger", ..."""
    dominant = model.vertex_bone_indices.gather(1, model.vertex_bone_weights.argmax(1, keepdim=True))[:, 0]
    stems = np.array([label.split(".")[0].rstrip("0123456789-") for label in model.bone_labels])
    return stems[dominant.numpy()]


#: Body part of the skin each bone moves; other bones (hands, neck, head) move skin.
_BONE_PARTS = {"root": "lower", "pelvis": "lower", "upperleg": "lower", "lowerleg": "shins", "foot": "shoes",
               "toe": "shoes", "spine": "upper", "clavicle": "upper", "shoulder": "upper", "upperarm": "upper",
               "lowerarm": "forearms"}


def _vertex_parts(model: anny.Anny, stems: np.ndarray, template_keypoints: np.ndarray) -> np.ndarray:
    """Body-part label of each vertex: its dominant bone's, the torso split at the waist, the head into face
    and scalp.

    anny's UV segmentation only separates head, hands and feet (and is lost with the retopology); the skinning
    weights separate every limb segment, at the joints where sleeves and trouser legs end. The waistband is
    8 cm above the hip joints. The scalp is the head above a hairline that runs from the forehead (5.5 cm above
    the eyes) over the ears (3 cm above their keypoint) down to the nape (4.5 cm below it). All are set on
    anny's template, in its rest frame (facing -y).
    """
    parts = np.array([BODY_PARTS.index(_BONE_PARTS.get(stem, "skin")) for stem in stems], dtype=np.uint8)
    vertices = model.template_vertices.numpy()
    keypoint = dict(zip(COCO_KEYPOINTS, template_keypoints, strict=True))

    torso = np.isin(stems, ("root", "pelvis", "spine"))
    waist = 0.5 * (keypoint["left_hip"][2] + keypoint["right_hip"][2]) + 0.08
    parts[torso] = np.where(vertices[torso, 2] < waist, BODY_PARTS.index("lower"), BODY_PARTS.index("upper"))

    eye_z = 0.5 * (keypoint["left_eye"][2] + keypoint["right_eye"][2])
    ear = 0.5 * (keypoint["left_ear"] + keypoint["right_ear"])
    behind_ear = vertices[:, 1] - ear[1]
    hairline = np.interp(behind_ear, [-0.06, -0.02, 0.01, 0.04],
                         [eye_z + 0.055, ear[2] + 0.03, ear[2] + 0.03, ear[2] - 0.045])
    parts[(stems == "head") & (vertices[:, 2] > hairline)] = BODY_PARTS.index("hair")
    return parts
