"""One labelled training sample of one region: people sampled, posed, rendered, composited and labelled.

Every sample is a pure function of (scene hash, region, sample index, seed) (docs/design.md, "Conventions"):
:func:`sample_rng` derives the one random generator a sample draws everything from — the number of people,
where they stand, their bodies, clothes and gait, the Mitsuba seed, and, when the scene has a sun course to follow
(:mod:`vc.render.sun_course`), the sun's position.

Compositing happens in linear light, in the order a camera works (:mod:`vc.render.effects`): the rendered
people and shadow layers go through the optics effects, the region's crop of the background photograph
(decoded with the camera response) is dimmed by the shadow layer and covered by the premultiplied people, the
sensor effects act on that linear composite, the response encodes it to 8 bits, and the encoding effects act
last. Labels come from the unaltered render passes (geometry), never from the effects' output.
"""

from __future__ import annotations

import hashlib
import math
import time
import zlib
from dataclasses import dataclass, field

import numpy as np

from vc.calibration.lighting import Illumination
from vc.io import read_image
from vc.render.appearance import WARDROBES, sample_appearance, vertex_albedo, vertex_thickness
from vc.render.bodies import BodyModel, sample_gait, sample_phenotype
from vc.render.dressing import dress
from vc.render.effects import MovingPerson, SampleLayers, build_effects
from vc.render.labels import PersonTruth, instance_map, person_annotation
from vc.render.people_renderer import PeopleRenderer, PersonGeometry
from vc.render.placement import PlacementSampler, default_max_people
from vc.render.plan import RenderPlan, region_background
from vc.render.relight import shading_render
from vc.render.sun_course import RATIO_SPP, moved_sun, shading_ratio
from vc.scenes.loader import Scene
from vc.scenes.regions import Region


@dataclass(frozen=True)
class SynthesisSettings:
    """What shapes every sample of a region (besides the scene itself)."""

    spp: int = 16
    seed: int = 0
    max_people: int | None = None  # per sample; None: from the region's ground area (see placement)


@dataclass
class RenderedSample:
    index: int
    image: np.ndarray  # (H, W, 3) uint8, the camera's encoding
    instances: np.ndarray  # (H, W) uint8: 0 nobody, k for the annotation whose instance_id is k
    annotations: list[dict]  # COCO annotation fields without ids (see vc.render.labels)
    depth: np.ndarray  # (H, W) float32 depth pass the keypoint visibility was decided from (not written out)
    timings: dict[str, float] = field(default_factory=dict)


def sample_rng(scene_hash: str, region_name: str, index: int, seed: int) -> np.random.Generator:
    """The random generator of one sample: a pure function of the scene, the region, the index and the seed."""
    scene_key = int(hashlib.sha256(scene_hash.encode()).hexdigest()[:16], 16)
    return np.random.default_rng(np.random.SeedSequence([seed, scene_key, zlib.crc32(region_name.encode()), index]))


def yaw_rotation(yaw_deg: float) -> np.ndarray:
    c, s = math.cos(math.radians(yaw_deg)), math.sin(math.radians(yaw_deg))
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


class RegionSynthesizer:
    """Renders the samples of one region; build once (a Mitsuba scene and the background), call per index."""

    def __init__(self, scene: Scene, region: Region, bodies: BodyModel, settings: SynthesisSettings,
                 plan: RenderPlan) -> None:
        self.scene, self.region, self.bodies, self.settings = scene, region, bodies, settings
        self.camera = region.camera(scene.camera)
        self.response = scene.camera_response().response
        self.background = self.response.decode(region_background(read_image(scene.image_path), region))
        self.placements = PlacementSampler(scene.camera, scene.layout, region.ground, scene.priors)
        self.max_people = settings.max_people if settings.max_people is not None else default_max_people(
            region.ground, scene.priors.m2_per_person)
        self.illumination, self.shadows = plan.illumination, plan.shadows
        self.renderer = self._people_renderer(plan.illumination)
        self.effects = build_effects(plan.effects, scene, region)
        # The sun's course (vc.render.sun_course): a renderer and a relit background per position, made when a
        # sample first needs one; the photographed position is the estimated light and the background as it is.
        self.sun_course = plan.sun_course
        self._lights: dict[int, tuple[PeopleRenderer, np.ndarray]] = {0: (self.renderer, self.background)}
        self._estimated_shading: np.ndarray | None = None  # what every position's relit background divides by

    def _people_renderer(self, illumination: Illumination) -> PeopleRenderer:
        return PeopleRenderer(self.camera, self.scene.layout, illumination, self.bodies.faces, self.bodies.vertex_count,
                              max(self.max_people, 1), self.settings.spp, shadows=self.shadows)

    def light(self, index: int) -> tuple[PeopleRenderer, np.ndarray]:
        """The renderer and the linear background of the sun course's position ``index`` (0: as photographed),
        built on first use (the background relit by :func:`vc.render.sun_course.shading_ratio`)."""
        if index not in self._lights:
            if self._estimated_shading is None:
                self._estimated_shading = shading_render(self.scene, self.illumination, RATIO_SPP)
            moved = moved_sun(self.illumination, self.sun_course[index])
            ratio = region_background(shading_ratio(self.scene, self.illumination, moved,
                                                    estimated_shading=self._estimated_shading), self.region)
            self._lights[index] = (self._people_renderer(moved), self.background * ratio)
        return self._lights[index]

    def sample(self, index: int) -> RenderedSample:
        timings: dict[str, float] = {}
        start = time.perf_counter()
        rng = sample_rng(self.scene.content_hash, self.region.name, index, self.settings.seed)
        placements = self.placements.sample(int(rng.integers(0, self.max_people + 1)), rng)
        phenotypes = [sample_phenotype(rng, tuple(self.scene.priors.height_m)) for _ in placements]
        gaits = [sample_gait(rng) for _ in placements]
        wardrobe = WARDROBES[self.scene.priors.clothing]
        appearances = [sample_appearance(rng, phenotype, wardrobe) for phenotype in phenotypes]
        render_seed = int(rng.integers(0, 2**32))
        effects_rng = np.random.default_rng(rng.integers(0, 2**63))
        # Drawn last, and only with a course: the samples of every other scene keep their bytes.
        light = int(rng.integers(0, len(self.sun_course))) if self.sun_course else 0
        posed = self.bodies.pose(phenotypes, gaits) if placements else None
        timings["pose"] = time.perf_counter() - start

        mark = time.perf_counter()
        dressed = [dress(posed.vertices[k], posed.keypoints[k], self.bodies.faces,
                         vertex_thickness(self.bodies.vertex_parts, appearances[k])) for k in range(len(placements))]
        timings["dress"] = time.perf_counter() - mark

        people, truths, moving = [], [], []
        for k, (placement, (body, joints)) in enumerate(zip(placements, dressed, strict=True)):
            rotation = yaw_rotation(placement.yaw_deg)
            offset = np.array([*placement.position, 0.0])
            vertices = (body.astype(np.float64) @ rotation.T + offset).astype(np.float32)
            keypoints = joints.astype(np.float64) @ rotation.T + offset
            people.append(PersonGeometry(vertices, vertex_albedo(self.bodies.vertex_parts, appearances[k])))
            moving.append(MovingPerson(centre=offset + np.array([0.0, 0.0, float(posed.stature_m[k]) / 2]),
                                       velocity=gaits[k].speed_mps * rotation[:, 0]))
            truths.append(PersonTruth(vertices=vertices, keypoints=keypoints, foot=offset,
                                      stature_m=float(posed.stature_m[k]), attributes={
                                          "position_m": [round(c, 4) for c in placement.position],
                                          "yaw_deg": round(placement.yaw_deg, 2),
                                          "height_m": round(float(posed.stature_m[k]), 4),
                                          "keypoints_m": np.round(keypoints, 4).tolist(),
                                          "placement": placement.kind,
                                          "phenotype": phenotypes[k].to_dict(),
                                          "gait": gaits[k].to_dict(),
                                          "appearance": appearances[k].to_dict(),
                                      }))
        mark = time.perf_counter()
        if light not in self._lights:
            built = time.perf_counter()
            self.light(light)
            timings["sun_course"] = time.perf_counter() - built
        renderer, background = self.light(light)
        passes = renderer.render(people, render_seed)
        timings["render"] = time.perf_counter() - mark
        timings.update({f"render.{step}": seconds for step, seconds in passes.timings.items()})

        mark = time.perf_counter()
        image = self._composite(passes, background, moving, effects_rng, timings)
        timings["composite"] = time.perf_counter() - mark

        mark = time.perf_counter()
        instances = instance_map(passes.coverage)
        annotations = []
        for k, truth in enumerate(truths):
            annotation = person_annotation(self.camera, truth, instances == k + 1, passes.depth)
            if annotation is not None:
                annotation["instance_id"] = k + 1
                annotations.append(annotation)
        timings["labels"] = time.perf_counter() - mark
        return RenderedSample(index, image, instances, annotations, passes.depth, timings)

    def _composite(self, passes, background: np.ndarray, moving: list[MovingPerson], rng: np.random.Generator,
                   timings: dict[str, float]) -> np.ndarray:
        """Optics effects on the layers, composite, sensor effects, encode, encoding effects (camera order)."""
        layers = SampleLayers(beauty=passes.beauty, coverage=passes.coverage, shadow=passes.shadow, people=moving)
        for effect in self.effects:
            if effect.stage == "optics":
                mark = time.perf_counter()
                effect.on_layers(layers, rng)
                timings[f"effect.{effect.name}"] = time.perf_counter() - mark
        alpha = layers.alpha
        linear = layers.beauty + (1.0 - alpha)[..., None] * background * layers.shadow
        for effect in self.effects:
            if effect.stage == "sensor":
                mark = time.perf_counter()
                linear = effect.on_linear(linear, alpha, rng)
                timings[f"effect.{effect.name}"] = time.perf_counter() - mark
        image = self.response.encode(linear)
        for effect in self.effects:
            if effect.stage == "encoding":
                mark = time.perf_counter()
                image = effect.on_encoded(image, rng)
                timings[f"effect.{effect.name}"] = time.perf_counter() - mark
        return image
