"""Camera effects: each decides whether the scene needs it and why, takes its parameters from the scene, and
acts on a sample where a camera would (docs/design.md, "Effects: simulate only what the scene calls for").

The order is the camera's:

1. **renderer** — lens distortion, cast shadows and the sun's course over the day are geometry and light: the people
   renderer produces them itself;
2. **optics** — motion blur, optical blur and vignetting act on the rendered people and shadow layers before
   they are composited, since the background photograph has been through the lens already;
3. **sensor** — noise, in linear light on the composite (shot noise grows with the signal);
4. **encoding** — the camera response turns linear light into 8 bits (:mod:`vc.calibration.response`), then
   block compression.

``effects: auto`` switches each effect on when the scene calls for it; an explicit list switches on exactly
the effects named (with parameters still measured from the scene). An effect that is off is never constructed
and costs nothing (:func:`build_effects` builds only those that are on). Labels never see an effect: they come
from geometry.

Frames of reference: the scene's effects are measured in full-frame pixels of the camera; each effect converts
to its region's network input, which is the crop window resized by ``region.scale``.
"""

from __future__ import annotations

import math
import time
from collections.abc import Sequence
from dataclasses import asdict, dataclass, field
from typing import ClassVar

import cv2
import numpy as np

from vc.calibration.camera import Camera
from vc.calibration.compression import jpeg_round_trip
from vc.calibration.lighting import Illumination
from vc.calibration.noise import NoiseModel
from vc.calibration.sharpness import added_blur, gaussian_blur
from vc.errors import InputError
from vc.render.camera_measurements import CameraMeasurements
from vc.render.relight import LightingFit
from vc.render.sun_course import MIN_ELEVATION_DEG, sun_positions
from vc.scenes.loader import Scene
from vc.scenes.regions import Region
from vc.scenes.schema import SolarLighting

#: Blur of the renderer's own pixels as :func:`vc.calibration.sharpness.estimate_blur_sigma` reads it: box-sampled
#: edges read 0.43 px (tests/test_sharpness.py), not the box filter's 1/sqrt(12), since the estimator's own pixel grid
#: blurs too; comparing like with like is what matters.
RENDER_BLUR_PX = 0.43
#: What warping a render through lens distortion adds: bilinear resampling at sub-pixel offsets ``f`` spread
#: evenly has a kernel variance of ``f (1 - f)``, 1/6 px^2 on average.
WARP_BLUR_VARIANCE_PX2 = 1.0 / 6.0
#: Optical blur is simulated when it adds at least this much (region pixels) to the people in some region.
MIN_ADDED_BLUR_PX = 0.25
#: Motion blur is simulated when a walker moves more than this many pixels during one exposure (docs/design.md).
MIN_MOTION_PX = 0.5
#: The walking speed the motion-blur decision assumes (m/s; the gait sampler's preferred speed).
WALKING_SPEED_MPS = 1.35
#: Sensor noise is simulated when the frames' noise at mid-grey is at least this many 8-bit levels.
MIN_NOISE_LEVELS = 0.5
#: Vignetting is simulated when the fitted fall-off darkens the image corners by more than this fraction, no more
#: than a lens does (cos^4 fall-off at a surveillance camera's field of view: 20-40 %; larger is the ground's
#: albedo, not the lens) ...
MIN_VIGNETTING, MAX_VIGNETTING = 0.10, 0.50
#: ... and explains at least this share of the background/re-render residual (see :func:`fit_vignetting`).
MIN_VIGNETTING_EXPLAINED = 0.30
#: Samples the plan times each effect on (the median is reported).
COST_REPEATS = 5


@dataclass(frozen=True)
class EffectDecision:
    """One effect in the plan: on or off, why, with which parameters, at what cost per sample."""

    name: str
    on: bool
    reason: str
    parameters: dict = field(default_factory=dict)
    ms_per_sample: float | None = None

    def to_dict(self) -> dict:
        return asdict(self)


@dataclass(frozen=True, eq=False)
class Evidence:
    """What the effects decide from."""

    scene: Scene
    regions: list[Region]
    illumination: Illumination
    lighting_fit: LightingFit | None
    camera: CameraMeasurements


@dataclass(frozen=True)
class MovingPerson:
    """A person's centre (world, metres) and velocity (m/s), for motion blur."""

    centre: np.ndarray
    velocity: np.ndarray


@dataclass
class SampleLayers:
    """The layers a sample is composited from, in region pixels; optics effects change them in place."""

    beauty: np.ndarray  # (H, W, 3) premultiplied linear radiance of the people
    coverage: np.ndarray  # (H, W, P) per person
    shadow: np.ndarray  # (H, W, 3) the factor people's shadows dim the background by
    people: list[MovingPerson]

    @property
    def alpha(self) -> np.ndarray:
        return self.coverage.sum(axis=-1) if self.coverage.shape[-1] else np.zeros(self.coverage.shape[:2],
                                                                                   np.float32)


class Effect:
    """One camera effect; subclasses implement :meth:`decide` and the stage methods that apply to them."""

    name: ClassVar[str]
    stage: ClassVar[str]  # "renderer", "optics", "sensor" or "encoding"

    def __init__(self, decision: EffectDecision, scene: Scene, region: Region) -> None:
        self.decision, self.scene, self.region = decision, scene, region

    @classmethod
    def decide(cls, evidence: Evidence) -> tuple[bool, str, dict]:
        """(whether the scene calls for it, why, its parameters)."""
        raise NotImplementedError

    @classmethod
    def requested(cls, evidence: Evidence) -> tuple[str, dict]:
        """(reason, parameters) when a scene lists the effect explicitly; the default uses :meth:`decide`'s
        parameters, and refuses when there is nothing to simulate."""
        needed, reason, parameters = cls.decide(evidence)
        if not parameters:
            raise InputError(evidence.scene.path, "effects", f"{cls.name} is listed, but {reason}")
        return "listed in the scene's effects" + ("" if needed else f" (auto would leave it off: {reason})"), \
            parameters

    def on_layers(self, layers: SampleLayers, rng: np.random.Generator) -> None:
        """Optics: change the people and shadow layers in place."""

    def on_linear(self, linear: np.ndarray, alpha: np.ndarray, rng: np.random.Generator) -> np.ndarray:
        """Sensor: the linear composite (and how much of each pixel is rendered rather than photographed)."""
        return linear

    def on_encoded(self, image: np.ndarray, rng: np.random.Generator) -> np.ndarray:
        """Encoding: the 8-bit image."""
        return image


# --- renderer --------------------------------------------------------------------------------------------------
class LensDistortion(Effect):
    name, stage = "lens_distortion", "renderer"

    @classmethod
    def decide(cls, evidence: Evidence) -> tuple[bool, str, dict]:
        distortion = evidence.scene.camera.distortion
        if distortion.is_identity:
            return False, "the calibration has no distortion", {}
        return True, "the calibration has non-zero distortion", {"model": type(distortion).__name__}


class Shadows(Effect):
    """People's shadows on the scene: cast by the sun, and the soft contact shadows of the sky they hide around
    their feet (under an overcast sky these are all there is, and they are still there)."""

    name, stage = "shadows", "renderer"

    @classmethod
    def decide(cls, evidence: Evidence) -> tuple[bool, str, dict]:
        light = evidence.illumination
        if light.has_sun:
            return True, "the light has a direct sun: cast shadows, and the sky's contact shadows", {
                "sun_azimuth_deg": round(light.sun_azimuth_deg, 2),
                "sun_elevation_deg": round(light.sun_elevation_deg, 2), "sun_to_sky": round(light.sun_to_sky, 3)}
        if max(light.sky_rgb) > 0:
            return True, "no direct sun: only the soft contact shadows of the sky people hide", {"sun_to_sky": 0.0}
        return False, "the scene has neither sun nor sky", {}

    @classmethod
    def requested(cls, evidence: Evidence) -> tuple[str, dict]:
        _, _, parameters = cls.decide(evidence)
        return "listed in the scene's effects", parameters


class SunCourse(Effect):
    """The sun over the background's day (:mod:`vc.render.sun_course`): each sample is lit by one of its positions,
    the layout's shadows and the people's cast where that position puts them. Only a scene that says where and when
    its background was taken has a course to follow."""

    name, stage = "sun_course", "renderer"

    @classmethod
    def decide(cls, evidence: Evidence) -> tuple[bool, str, dict]:
        lighting = evidence.scene.lighting
        if not isinstance(lighting, SolarLighting):
            return False, "the scene does not say where and when its background was taken (lighting: {location, " \
                          "time, north_deg}): its one sun is kept", {}
        if not evidence.illumination.has_sun:
            return False, "the background shows no direct sun: there are no hard shadows to move", {}
        positions = sun_positions(lighting)
        if len(positions) < 2:
            return False, f"the sun stands {MIN_ELEVATION_DEG:g} degrees high at no hour of the background's date", {}
        moved = positions[1:]
        return True, f"the scene says where and when: the photographed sun and {len(moved)} positions of " \
                     f"{lighting.time.date().isoformat()} ({moved[0].time[11:16]}-{moved[-1].time[11:16]}, at least " \
                     f"{MIN_ELEVATION_DEG:g} degrees high), one per sample", \
            {"positions": [position.to_dict() for position in positions]}


# --- optics ----------------------------------------------------------------------------------------------------
def _region_scale(region: Region) -> float:
    return float(np.sqrt(region.scale[0] * region.scale[1]))


def _line_kernel(motion: np.ndarray) -> np.ndarray:
    """A normalised, antialiased line of the length and direction of ``motion`` (dx, dy) pixels."""
    half = int(math.ceil(float(np.abs(motion).max()) / 2)) + 1
    kernel = np.zeros((2 * half + 1, 2 * half + 1), np.float32)
    start, end = half - motion / 2, half + motion / 2
    cv2.line(kernel, tuple(np.round(start * 16).astype(int)), tuple(np.round(end * 16).astype(int)), 1.0, 1,
             cv2.LINE_AA, shift=4)
    if kernel.sum() <= 0:
        kernel[half, half] = 1.0
    return kernel / kernel.sum()


class MotionBlur(Effect):
    """People move during the exposure: each person's layers are smeared along their projected velocity."""

    name, stage = "motion_blur", "optics"

    def __init__(self, decision: EffectDecision, scene: Scene, region: Region) -> None:
        super().__init__(decision, scene, region)
        self.exposure_s = decision.parameters["exposure_s"]
        self.camera: Camera = region.camera(scene.camera)

    @classmethod
    def decide(cls, evidence: Evidence) -> tuple[bool, str, dict]:
        scene = evidence.scene
        if scene.exposure_s is None:
            return False, "the camera's exposure time is not known (give camera.exposure_s to simulate it)", {}
        pixels_per_m = max(max(region.person_px) / scene.priors.height_m[0] / region.scale[1]
                           for region in evidence.regions)
        travel = WALKING_SPEED_MPS * scene.exposure_s * pixels_per_m
        parameters = {"exposure_s": scene.exposure_s, "walker_travel_px": round(travel, 3)}
        if travel <= MIN_MOTION_PX:
            return False, (f"a walker moves {travel:.2f} px during the {scene.exposure_s * 1000:.1f} ms exposure "
                           f"(<= {MIN_MOTION_PX} px)"), parameters
        return True, f"a walker moves up to {travel:.2f} px during the {scene.exposure_s * 1000:.1f} ms exposure", \
            parameters

    def _motion_px(self, person: MovingPerson) -> np.ndarray:
        travel = person.velocity * self.exposure_s
        ends = self.camera.project(np.stack([person.centre - travel / 2, person.centre + travel / 2]))
        return ends.uv[1] - ends.uv[0] if ends.ok.all() else np.zeros(2)

    def on_layers(self, layers: SampleLayers, rng: np.random.Generator) -> None:
        alpha = layers.alpha
        share = np.where(alpha[..., None] > 1e-6, layers.coverage / np.maximum(alpha, 1e-6)[..., None], 0.0)
        beauty = np.zeros_like(layers.beauty)
        coverage = np.zeros_like(layers.coverage)
        for index, person in enumerate(layers.people):
            motion = self._motion_px(person)
            own_beauty = layers.beauty * share[..., index:index + 1]
            own_coverage = layers.coverage[..., index]
            if np.abs(motion).max() < MIN_MOTION_PX:
                beauty += own_beauty
                coverage[..., index] = own_coverage
                continue
            kernel = _line_kernel(motion)
            beauty += cv2.filter2D(own_beauty, -1, kernel, borderType=cv2.BORDER_CONSTANT)
            coverage[..., index] = cv2.filter2D(own_coverage, -1, kernel, borderType=cv2.BORDER_CONSTANT)
        layers.beauty, layers.coverage = beauty.astype(np.float32), coverage.astype(np.float32)


def render_blur_px(camera: Camera) -> float:
    """The renderer's own blur in its pixels: box sampling, and the distortion warp's resampling if any."""
    warp = 0.0 if camera.distortion.is_identity else WARP_BLUR_VARIANCE_PX2
    return math.sqrt(RENDER_BLUR_PX**2 + warp)


class OpticalBlur(Effect):
    """People are never sharper than the scene: they get the blur the background's edges show."""

    name, stage = "optical_blur", "optics"

    def __init__(self, decision: EffectDecision, scene: Scene, region: Region) -> None:
        super().__init__(decision, scene, region)
        self.sigma = decision.parameters["added_sigma_px"][region.name]

    @classmethod
    def decide(cls, evidence: Evidence) -> tuple[bool, str, dict]:
        blur = evidence.camera.blur
        if blur.edges == 0:
            return False, "the background shows no edges to measure its blur on", {}
        parameters = {"scene_sigma_px": round(blur.sigma_px, 3), "edges": blur.edges}
        own = render_blur_px(evidence.scene.camera)
        added = {region.name: round(added_blur(blur.sigma_px * _region_scale(region), own), 3)
                 for region in evidence.regions}
        parameters["added_sigma_px"] = added
        if max(added.values()) < MIN_ADDED_BLUR_PX:
            return False, (f"the background's edges are as sharp as the renders (sigma {blur.sigma_px:.2f} px)"), \
                parameters
        return True, (f"the background's edges are blurred (sigma {blur.sigma_px:.2f} px over {blur.edges} edge "
                      "pixels)"), parameters

    def on_layers(self, layers: SampleLayers, rng: np.random.Generator) -> None:
        if self.sigma <= 0:
            return
        layers.beauty = gaussian_blur(layers.beauty, self.sigma)
        layers.coverage = gaussian_blur(layers.coverage, self.sigma) if layers.coverage.shape[-1] else layers.coverage
        layers.shadow = gaussian_blur(layers.shadow, self.sigma)


def fit_vignetting(camera: Camera, fit: LightingFit, stride: int = 4) -> tuple[float, float]:
    """Radial fall-off of background over re-render on known ground: ``log V = a r^2`` with ``r`` the distance
    from the principal point over the half diagonal, beside one offset per kind of ground (vegetation, paved), so
    that a lawn darker than its prior in the image's corners is not taken for the lens. Returns (``1 - exp(a)``:
    the corners' darkening, the share of the residual variance left by the offsets that the fall-off explains)."""
    known = fit.known_ground[::stride, ::stride]
    residual = -fit.log_error()[::stride, ::stride] * math.log(2.0)
    usable = known & np.isfinite(residual)
    if usable.sum() < 100:
        return 0.0, 0.0
    ys, xs = np.nonzero(usable)
    half_diagonal = math.hypot(camera.width, camera.height) / 2
    radius2 = ((xs * stride - camera.cx) ** 2 + (ys * stride - camera.cy) ** 2) / half_diagonal**2
    vegetation = fit.vegetation[::stride, ::stride][usable].astype(np.float64)
    values = residual[usable]
    kinds = np.stack([vegetation, 1.0 - vegetation], axis=1)
    with_falloff = np.concatenate([radius2[:, None], kinds], axis=1)

    def squared_error(design: np.ndarray) -> tuple[float, np.ndarray]:
        coefficients, *_ = np.linalg.lstsq(design, values, rcond=None)
        return float(((values - design @ coefficients) ** 2).sum()), coefficients

    without, _ = squared_error(kinds)
    within, coefficients = squared_error(with_falloff)
    explained = (without - within) / without if without > 0 else 0.0
    return 1.0 - math.exp(coefficients[0]), explained


class Vignetting(Effect):
    """The lens darkens the image towards its corners; rendered people get the same fall-off."""

    name, stage = "vignetting", "optics"

    def __init__(self, decision: EffectDecision, scene: Scene, region: Region) -> None:
        super().__init__(decision, scene, region)
        camera = scene.camera
        darkening = decision.parameters["corner_darkening"]
        width, height = region.input_size
        scale_x, scale_y = region.scale
        xs = region.crop.x0 + (np.arange(width) + 0.5) / scale_x - 0.5
        ys = region.crop.y0 + (np.arange(height) + 0.5) / scale_y - 0.5
        half_diagonal = math.hypot(camera.width, camera.height) / 2
        radius2 = ((xs[None, :] - camera.cx) ** 2 + (ys[:, None] - camera.cy) ** 2) / half_diagonal**2
        self.falloff = np.exp(math.log(1.0 - darkening) * radius2).astype(np.float32)

    @classmethod
    def decide(cls, evidence: Evidence) -> tuple[bool, str, dict]:
        if evidence.lighting_fit is None:
            return False, "no re-render of the empty scene to measure it against", {}
        darkening, explained = fit_vignetting(evidence.scene.camera, evidence.lighting_fit)
        parameters = {"corner_darkening": round(darkening, 4), "explained": round(explained, 3)}
        if not MIN_VIGNETTING <= darkening <= MAX_VIGNETTING or explained < MIN_VIGNETTING_EXPLAINED:
            return False, (f"no lens fall-off stands out from the ground's own variation (corners {darkening:+.0%} "
                           f"darker, explaining {explained:.0%} of the residual)"), parameters
        return True, (f"the background darkens towards its corners by {darkening:.0%} beyond the re-render "
                      f"(explaining {explained:.0%} of the residual)"), parameters

    def on_layers(self, layers: SampleLayers, rng: np.random.Generator) -> None:
        layers.beauty = layers.beauty * self.falloff[..., None]


# --- sensor ----------------------------------------------------------------------------------------------------
def _crop_sized(region: Region) -> tuple[int, int]:
    return region.crop.width, region.crop.height


class SensorNoise(Effect):
    """Shot and read noise as the frames show it, on the composite in linear light; the noise the background
    photograph already carries is not added twice."""

    name, stage = "sensor_noise", "sensor"

    def __init__(self, decision: EffectDecision, scene: Scene, region: Region) -> None:
        super().__init__(decision, scene, region)
        self.frames = NoiseModel(**decision.parameters["frames"])
        self.background = NoiseModel(**decision.parameters["background"])

    @classmethod
    def decide(cls, evidence: Evidence) -> tuple[bool, str, dict]:
        measured = evidence.camera
        frames, background = measured.frame_noise, measured.background_noise
        parameters = {"frames": frames.model.to_dict(), "background": background.model.to_dict(),
                      "frames_sigma_8bit": round(frames.sigma_at_mid_grey_8bit, 3),
                      "background_sigma_8bit": round(background.sigma_at_mid_grey_8bit, 3),
                      "measured_on": measured.frames_source}
        if frames.samples == 0:
            return False, "no flat area or static pixel to measure noise on", {}
        if frames.sigma_at_mid_grey_8bit < MIN_NOISE_LEVELS:
            return False, (f"the frames' noise is {frames.sigma_at_mid_grey_8bit:.2f} 8-bit levels at mid-grey "
                           f"(< {MIN_NOISE_LEVELS})"), parameters
        return True, (f"the frames' noise is {frames.sigma_at_mid_grey_8bit:.2f} 8-bit levels at mid-grey, the "
                      f"background's {background.sigma_at_mid_grey_8bit:.2f}"), parameters

    def on_linear(self, linear: np.ndarray, alpha: np.ndarray, rng: np.random.Generator) -> np.ndarray:
        # Unit noise at the camera's own resolution, resized as the network input resizes real frames.
        width, height = _crop_sized(self.region)
        unit = cv2.resize(rng.standard_normal((height, width, 3), dtype=np.float32), self.region.input_size,
                          interpolation=cv2.INTER_LINEAR)
        photographed = (1.0 - np.clip(alpha, 0.0, 1.0))[..., None] ** 2
        return self.frames.apply(linear, rng, keep_variance=photographed * self.background.variance(linear),
                                 unit=unit)


# --- encoding --------------------------------------------------------------------------------------------------
class Compression(Effect):
    """Block-DCT compression (JPEG, with 4:2:0 chroma when the frames show it) at the frames' quality, applied at
    the camera's resolution: the artefact is computed on the crop window and resized with the image."""

    name, stage = "jpeg", "encoding"

    @classmethod
    def decide(cls, evidence: Evidence) -> tuple[bool, str, dict]:
        measured = evidence.camera
        compression = measured.compression
        if compression.quality is None:
            blocking = compression.evidence.get("frame_blockiness")
            seen = "" if blocking is None else (f" (blockiness {blocking:.3f}, the background with the frames' noise "
                                                f"{compression.evidence['noisy_background_blockiness']:.3f})")
            return False, f"no block compression found in {measured.frames_source}{seen}", {}
        parameters = {"quality": int(compression.quality), "chroma_subsampling": bool(compression.chroma_subsampling),
                      "measured_on": measured.frames_source}
        return True, (f"{measured.frames_source} show block compression at quality about {compression.quality}"
                      + (" with 4:2:0 chroma" if compression.chroma_subsampling else "")), parameters

    def on_encoded(self, image: np.ndarray, rng: np.random.Generator) -> np.ndarray:
        size = _crop_sized(self.region)
        camera_sized = cv2.resize(image, size, interpolation=cv2.INTER_LINEAR) if size != image.shape[1::-1] \
            else image
        compressed = jpeg_round_trip(camera_sized, self.decision.parameters["quality"],
                                     self.decision.parameters["chroma_subsampling"])
        artefact = compressed.astype(np.float32) - camera_sized.astype(np.float32)
        if size != image.shape[1::-1]:
            artefact = cv2.resize(artefact, image.shape[1::-1], interpolation=cv2.INTER_LINEAR)
        return np.clip(np.round(image.astype(np.float32) + artefact), 0, 255).astype(np.uint8)


class Defocus(Effect):
    name, stage = "defocus", "optics"

    @classmethod
    def decide(cls, evidence: Evidence) -> tuple[bool, str, dict]:
        return False, "surveillance cameras are focused over their ground range; optical_blur carries the " \
                      "scene's measured blur", {}

    @classmethod
    def requested(cls, evidence: Evidence) -> tuple[str, dict]:
        raise InputError(evidence.scene.path, "effects", "defocus is not simulated: list optical_blur, which "
                                                         "applies the blur measured on the background")


#: Every effect, in the order a camera applies them.
REGISTRY: tuple[type[Effect], ...] = (LensDistortion, Shadows, SunCourse, MotionBlur, OpticalBlur, Vignetting,
                                      Defocus, SensorNoise, Compression)
STAGES = ("renderer", "optics", "sensor", "encoding")


def plan_effects(evidence: Evidence) -> list[EffectDecision]:
    """Each effect on or off with its reason and parameters (costs are added by :func:`with_costs`)."""
    scene = evidence.scene
    explicit = None if scene.effects == "auto" else set(scene.effects)
    decisions = []
    for effect in REGISTRY:
        if explicit is None:
            on, reason, parameters = effect.decide(evidence)
        elif effect.name in explicit:
            on, (reason, parameters) = True, effect.requested(evidence)
        elif effect is LensDistortion and not scene.camera.distortion.is_identity:
            raise InputError(scene.path, "effects", "lens_distortion cannot be left out: the calibration has lens "
                                                    "distortion and the labels must follow the real lens")
        else:
            on, reason, parameters = False, "not listed in the scene's effects", {}
        decisions.append(EffectDecision(effect.name, on, reason, parameters))
    return decisions


def effect_on(decisions: Sequence[EffectDecision], name: str) -> bool:
    return any(decision.on for decision in decisions if decision.name == name)


def build_effects(decisions: Sequence[EffectDecision], scene: Scene, region: Region) -> list[Effect]:
    """The effects that are on and act on samples (not the renderer's own), in camera order, for ``region``."""
    by_name = {effect.name: effect for effect in REGISTRY}
    built = [by_name[decision.name](decision, scene, region) for decision in decisions
             if decision.on and by_name[decision.name].stage != "renderer"]
    return sorted(built, key=lambda effect: STAGES.index(effect.stage))


def _probe_layers(region: Region, background: np.ndarray) -> SampleLayers:
    """A sample-sized stand-in for timing: one person-sized block of coverage in the middle of the input, walking
    at the middle of the region's ground."""
    width, height = region.input_size
    coverage = np.zeros((height, width, 1), np.float32)
    person_h = int(min(height, max(region.person_px) * region.scale[1]))
    person_w = max(person_h // 3, 1)
    top, left = (height - person_h) // 2, (width - person_w) // 2
    coverage[top:top + person_h, left:left + person_w] = 1.0
    beauty = coverage * background * 0.5
    centre = region.ground.centroid
    walker = MovingPerson(np.array([centre.x, centre.y, 0.9]), np.array([WALKING_SPEED_MPS, 0.0, 0.0]))
    return SampleLayers(beauty=beauty, coverage=coverage, shadow=np.ones_like(background), people=[walker])


def time_effect(effect: Effect, background: np.ndarray, repeats: int = COST_REPEATS) -> float:
    """Median milliseconds one sample of ``effect``'s region spends in it (on a stand-in sample)."""
    rng = np.random.default_rng(0)
    times = []
    for _ in range(repeats):
        layers = _probe_layers(effect.region, background)
        start = time.perf_counter()
        effect.on_layers(layers, rng)
        linear = effect.on_linear(background.copy(), layers.alpha, rng)
        effect.on_encoded(np.clip(linear * 255, 0, 255).astype(np.uint8), rng)
        times.append(time.perf_counter() - start)
    return 1000.0 * float(np.median(times))
