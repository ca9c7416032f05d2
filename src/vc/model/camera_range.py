"""What the camera will see besides its one image: every training window's composite (background and people
together) varied over the camera's life — exposure, white balance, IR night mode, gain noise, blur, compression.

A bundle learned from one background exposed one way took anything that departed from that look for people: two
stops less light, a white-balance drift, the IR night mode each made it invent tens of people on the empty scene
(issue 62). A camera in service meets all of these every day, so the composite varies over them, background and
people alike, and the network learns that a person is a shape, not a departure from the background's colour.

Why on the training windows and not in the render: the variation acts on the whole composite, which the dataset
stores already encoded; decoding it through the scene's camera response gives the linear light back (to an 8-bit
level), so each draw of a window gets its own condition at a fraction of a millisecond, where a render-time draw
would fix one condition per stored sample and cost a re-render to change a range. The order is the camera's, in
linear light (:meth:`CameraLife.apply`):

1. **night mode** — IR monochrome: every channel becomes one mix of the three, its weights drawn (materials reflect
   near-infrared unlike visible light; the mix stands in for that), on :attr:`CameraRange.night_ir` of the draws;
2. **white balance** — a residual cast the camera's white balance leaves: the light's colour temperature off the
   balanced one by up to :attr:`CameraRange.white_balance_mired` (Planckian locus, colour-science) and a green tint;
3. **blur** — a dirty or wet lens, focus drift: a Gaussian of up to :attr:`CameraRange.blur_sigma_px` camera pixels;
4. **exposure and gain** — the light changes by ``s`` stops within :attr:`CameraRange.exposure_stops`; below the
   scene's light the sensor collects fewer photons, so the shot and read noise of that darker exposure (the frames'
   measured noise model) is added, and the camera's gain then recovers part of the brightness, amplifying that
   noise: the dusk frame that is dark, or bright and grainy;
5. **encoding** — the camera response back to 8 bits, then block compression at a quality drawn from
   :attr:`CameraRange.jpeg_quality` on a share of the draws.

A share :attr:`CameraRange.varied` of the draws is varied; the rest keep the look the scene was calibrated to, which
stays the common case. Geometry is not varied: a nudged camera moves the picture by a few pixels, which the fully
convolutional network already meets as the training windows' random positions (a window is cut anywhere).
Every draw is a pure function of the stream's generator, as the rest of a training item is.
"""

from __future__ import annotations

import math
import time
from dataclasses import asdict, dataclass

import colour
import cv2
import numpy as np

from vc.calibration.compression import jpeg_round_trip
from vc.calibration.noise import NoiseModel
from vc.calibration.response import Response
from vc.deploy.fitness import (
    BLURRED_SHARPNESS,
    COLOUR_CAST_STOPS,
    DARK_STOPS,
    OVEREXPOSED_STOPS,
    FitRange,
    SceneReference,
)

#: The colour temperature a camera's white balance is taken to be set for (K): sRGB's white, D65's.
BALANCED_CCT_K = 6504.0
#: Side of the bank of unit noise a stream draws once and crops per draw (drawing fresh noise per window cost 1.5 ms
#: of the loader's time, which is the training step's on a CPU).
NOISE_BANK_PX = 512
#: Draws the cost of the variation is timed on (the mean is reported).
COST_REPEATS = 20
#: A frame is fit up to this many stops beyond the exposures the range renders, as the scene fitness reads them.
FIT_MARGIN_STOPS = 0.25
#: ... down to this share of the sharpness of the most blur it renders ...
FIT_SHARPNESS_MARGIN = 0.8
#: ... and up to this much more colour cast than its strongest white-balance error.
FIT_CAST_MARGIN_STOPS = 0.1


@dataclass(frozen=True)
class CameraRange:
    """The ranges a camera's frames vary over in service; the defaults are a day-and-night outdoor camera's."""

    #: Read strictly when pydantic validates a stored training config (:func:`vc.model.trainer.read_train_config`).
    __pydantic_config__ = {"extra": "forbid"}

    #: Light over the scene's (stops): from dusk before the night mode switches on (three stops under a grey
    #: day) and an auto-exposure lagging a cloud, to a bright sun on the ground.
    exposure_stops: tuple[float, float] = (-3.0, 1.0)
    #: Residual white-balance error (mired, either way): auto white balance under mixed or changing light stays
    #: within about 50; R x1.25 / B x0.8 is 45.
    white_balance_mired: float = 75.0
    #: Green-magenta tint (log2 of the green gain, either way).
    tint_stops: float = 0.1
    #: Share of varied draws in IR monochrome: most surveillance cameras switch to it at night (0: a camera without
    #: a night mode).
    night_ir: float = 0.15
    #: Share of varied draws blurred, and the most blur (Gaussian sigma, camera pixels): a wet or dirty lens.
    blurred: float = 0.25
    blur_sigma_px: float = 2.0
    #: Share of varied draws block-compressed, at a JPEG quality within this range (a stream's bitrate dropping).
    compressed: float = 0.25
    jpeg_quality: tuple[int, int] = (30, 90)
    #: Share of the draws varied at all; the rest keep the look the scene was calibrated to.
    varied: float = 0.75

    def __post_init__(self) -> None:
        low, high = self.exposure_stops
        if not low <= 0.0 <= high:
            raise ValueError(f"exposure_stops {self.exposure_stops} must hold 0 (the scene's own exposure)")
        for name in ("night_ir", "blurred", "compressed", "varied"):
            if not 0.0 <= getattr(self, name) <= 1.0:
                raise ValueError(f"{name} is a share of draws, between 0 and 1")
        if self.white_balance_mired < 0 or self.tint_stops < 0 or self.blur_sigma_px < 0:
            raise ValueError("white_balance_mired, tint_stops and blur_sigma_px are ranges either way: not negative")
        quality_low, quality_high = self.jpeg_quality
        if not 1 <= quality_low <= quality_high <= 100:
            raise ValueError(f"jpeg_quality {self.jpeg_quality} must be 1 <= low <= high <= 100")
        if 1e6 / BALANCED_CCT_K + self.white_balance_mired >= 1e6 / 1667.0:
            raise ValueError("white_balance_mired reaches below 1667 K, the end of the Planckian locus")

    def to_dict(self) -> dict:
        return asdict(self)


def _planckian_rgb(cct_k: float) -> np.ndarray:
    xyz = colour.xy_to_XYZ(colour.temperature.CCT_to_xy_Kang2002(cct_k))
    return np.asarray(colour.XYZ_to_RGB(xyz, "sRGB", apply_cctf_encoding=False), np.float64)


def white_balance_gains(mired_shift: float) -> np.ndarray:
    """(3,) linear RGB gains, green 1, that a light ``mired_shift`` mired warmer (positive) than the balanced one
    leaves in a camera balanced for :data:`BALANCED_CCT_K` (von Kries in the camera's RGB, taken as sRGB's)."""
    cct = 1e6 / (1e6 / BALANCED_CCT_K + mired_shift)
    gains = _planckian_rgb(cct) / _planckian_rgb(BALANCED_CCT_K)
    return (gains / gains[1]).astype(np.float32)


@dataclass(frozen=True)
class Condition:
    """One draw's camera condition (what :meth:`CameraLife.apply` did to a window)."""

    stops: float = 0.0
    recovered_stops: float = 0.0  # of the light lost, what the camera's gain brought back
    gains: tuple[float, float, float] = (1.0, 1.0, 1.0)
    ir_mix: tuple[float, float, float] | None = None
    blur_sigma_px: float = 0.0  # window pixels
    jpeg_quality: int | None = None

    @property
    def unchanged(self) -> bool:
        return self == Condition()


class CameraLife:
    """A :class:`CameraRange` acting on one region's training windows: built from the dataset's camera response,
    the frames' measured noise and the region's scale (window pixels per camera pixel)."""

    #: Mireds tabulated for the white balance (interpolated between; colour-science costs 0.1 ms a call).
    _MIRED_STEPS = 61

    def __init__(self, camera_range: CameraRange, response: Response, noise: NoiseModel, region_scale: float,
                 seed: int = 0) -> None:
        self.range, self.response, self.noise, self.region_scale = camera_range, response, noise, region_scale
        limit = camera_range.white_balance_mired
        self._mireds = np.linspace(-limit, limit, self._MIRED_STEPS) if limit > 0 else np.zeros(1)
        self._gains = np.stack([white_balance_gains(float(mired)) for mired in self._mireds])
        self._noise_bank = np.random.default_rng([seed, 0x4C494645]).standard_normal(
            (NOISE_BANK_PX, NOISE_BANK_PX, 3), dtype=np.float32)

    def draw(self, rng: np.random.Generator) -> Condition:
        """A condition from the ranges (the unchanged one for the share not varied)."""
        spec = self.range
        if rng.random() >= spec.varied:
            return Condition()
        low, high = spec.exposure_stops
        stops = float(rng.uniform(low, high))
        recovered = float(rng.uniform(0.0, -stops)) if stops < 0 else 0.0
        ir_mix = None
        if rng.random() < spec.night_ir:
            ir_mix = tuple(float(weight) for weight in rng.dirichlet((2.0, 2.0, 2.0)))
            gains = (1.0, 1.0, 1.0)
        else:
            mired = float(rng.uniform(-spec.white_balance_mired, spec.white_balance_mired))
            gains = np.array([np.interp(mired, self._mireds, self._gains[:, channel]) for channel in range(3)])
            gains[1] *= 2.0 ** float(rng.uniform(-spec.tint_stops, spec.tint_stops))
            gains = tuple(float(gain) for gain in gains)
        blur = float(rng.uniform(0.0, spec.blur_sigma_px)) * self.region_scale if rng.random() < spec.blurred else 0.0
        quality = int(rng.integers(spec.jpeg_quality[0], spec.jpeg_quality[1] + 1)) \
            if rng.random() < spec.compressed else None
        return Condition(stops, recovered, gains, ir_mix, blur, quality)

    def apply(self, image: np.ndarray, rng: np.random.Generator) -> np.ndarray:
        """``image`` ((H, W, 3) uint8, the camera's encoding) under a condition drawn from ``rng``, uint8."""
        condition = self.draw(rng)
        return image if condition.unchanged else self.render(image, condition, rng)

    def render(self, image: np.ndarray, condition: Condition, rng: np.random.Generator) -> np.ndarray:
        """``image`` under ``condition`` (module docstring, steps 1-5)."""
        linear = self.response.decode(image)
        if condition.ir_mix is not None:
            mono = linear @ np.asarray(condition.ir_mix, np.float32)
            linear = np.repeat(mono[..., None], 3, axis=2)
        else:
            linear = linear * np.asarray(condition.gains, np.float32)
        if condition.blur_sigma_px > 0:
            linear = cv2.GaussianBlur(linear, (0, 0), condition.blur_sigma_px)
        if condition.stops != 0.0:
            light = np.float32(2.0 ** condition.stops)
            linear = linear * light
            if condition.stops < 0:
                linear = linear + self._darker_exposure_noise(linear, light, rng)
                linear *= np.float32(2.0 ** condition.recovered_stops)
        encoded = self.response.encode(linear)
        if condition.jpeg_quality is not None:
            encoded = jpeg_round_trip(encoded, condition.jpeg_quality, chroma_subsampling=True)
        return encoded

    def _darker_exposure_noise(self, linear: np.ndarray, light: np.float32, rng: np.random.Generator) -> np.ndarray:
        """The noise a darker exposure has and the stored window (the scene's exposure, scaled by ``light``) lacks:
        at linear value ``x`` the sensor's variance is ``shot x + read^2``, the scaled window's ``light (shot x +
        light read^2)``; the difference, with unit noise cropped from the stream's bank."""
        missing = self.noise.shot * (1.0 - light) * np.clip(linear, 0.0, None) \
            + np.float32(self.noise.read ** 2 * (1.0 - light * light))
        height, width = linear.shape[:2]
        unit = self._unit_noise(height, width, rng)
        return unit * np.sqrt(missing, dtype=np.float32)

    def _unit_noise(self, height: int, width: int, rng: np.random.Generator) -> np.ndarray:
        if height > NOISE_BANK_PX or width > NOISE_BANK_PX:
            return rng.standard_normal((height, width, 3), dtype=np.float32)
        y0 = int(rng.integers(0, NOISE_BANK_PX - height + 1))
        x0 = int(rng.integers(0, NOISE_BANK_PX - width + 1))
        return self._noise_bank[y0:y0 + height, x0:x0 + width]


def describe(camera_range: CameraRange | None, noise: NoiseModel, response: Response) -> list[tuple[str, bool, str]]:
    """Each variation (name, on, why), for the training plan's lines (:func:`plan_lines`)."""
    if camera_range is None:
        return [("camera range", False, "off: every window keeps the look the scene was calibrated to")]
    spec = camera_range
    low, high = spec.exposure_stops
    return [
        ("exposure", low < high, f"{low:+.1f} to {high:+.1f} stops of light through the {response.name} response, "
                                 "dusk to bright sun"),
        ("gain noise", low < 0 and (noise.shot > 0 or noise.read > 0),
         f"the darker exposures' shot and read noise from the frames' model (shot {noise.shot:.2e}), amplified by "
         "the gain that recovers part of the light"),
        ("white balance", spec.white_balance_mired > 0 or spec.tint_stops > 0,
         f"casts up to {spec.white_balance_mired:.0f} mired and {spec.tint_stops:.2f} stops of green either way"),
        ("night IR", spec.night_ir > 0, f"{spec.night_ir:.0%} of the varied windows in IR monochrome"
         + ("" if spec.night_ir > 0 else " (the camera has no night mode)")),
        ("blur", spec.blurred > 0 and spec.blur_sigma_px > 0,
         f"{spec.blurred:.0%} of the varied windows blurred up to sigma {spec.blur_sigma_px:.1f} camera px"),
        ("compression", spec.compressed > 0,
         f"{spec.compressed:.0%} of the varied windows at JPEG quality {spec.jpeg_quality[0]}-{spec.jpeg_quality[1]}"),
    ]


def time_draw(life: CameraLife, size: tuple[int, int], repeats: int = COST_REPEATS) -> float:
    """Mean milliseconds a window of ``size`` (width, height) spends being varied, over the draws (unchanged ones
    included: what a training step pays on average)."""
    rng = np.random.default_rng(0)
    window = rng.integers(0, 256, (size[1], size[0], 3), dtype=np.uint8)
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        life.apply(window, rng)
        times.append(time.perf_counter() - start)
    return 1000.0 * float(np.mean(times))


def camera_life_of(manifest: dict, region: dict, camera_range: CameraRange, seed: int) -> CameraLife:
    """The range acting on one region (its ``region`` entry) of a dataset (its ``manifest``): the camera response
    and the frames' noise model as the render plan measured them (a dataset older than the plan: sRGB, no gain
    noise), the region's scale (input over crop window)."""
    response = Response((manifest.get("response") or {}).get("name", "srgb"))
    model = ((manifest.get("camera_measurements") or {}).get("frame_noise") or {}).get("model")
    noise = NoiseModel(**model) if model else NoiseModel(0.0, 0.0)
    (width, height), crop = region["input_size"], region["crop_window"]
    return CameraLife(camera_range, response, noise, math.sqrt(width / crop[2] * height / crop[3]), seed)


def plan_lines(manifest: dict, regions: dict[str, dict], camera_range: CameraRange | None) -> list[str]:
    """The camera range as a training plan shows it: each variation on or off and why, and what a window of the
    largest region costs on average (timed here)."""
    if camera_range is None:
        return ["camera range  off: every window keeps the look the scene was calibrated to"]
    largest = max(regions.values(), key=lambda entry: entry["input_size"][0] * entry["input_size"][1])
    life = camera_life_of(manifest, largest, camera_range, seed=0)
    size = tuple(min(side, 256) for side in largest["input_size"])
    lines = [f"camera range  {camera_range.varied:.0%} of the windows varied, "
             f"{time_draw(life, size):.2f} ms per {size[0]}x{size[1]} window on average"]
    for name, on, reason in describe(camera_range, life.noise, life.response):
        lines.append(f"  {'on ' if on else 'off'}  {name:<14} {reason}")
    return lines


def fit_range_of(camera_range: CameraRange | None, reference: SceneReference, background: np.ndarray,
                 response: Response) -> FitRange:
    """What a bundle compiled over ``camera_range`` sees, as the scene fitness reads frames: the ``background``
    ((H, W, 3) uint8, the reference's) rendered at the range's ends — its darkest and brightest exposures, its most
    blur, its strongest white-balance casts — and measured against ``reference``, with a margin beyond each
    (:data:`FIT_MARGIN_STOPS`, :data:`FIT_SHARPNESS_MARGIN`, :data:`FIT_CAST_MARGIN_STOPS`); never tighter than
    the background's own look (:class:`FitRange`'s defaults). Monochrome frames are fit when the range has a
    night mode. Measured, not derived, because the fitness reads through coarse cells and clipping: the
    measurement is what a frame at the range's end will read."""
    if camera_range is None:
        return FitRange()
    life = CameraLife(camera_range, response, NoiseModel(0.0, 0.0), region_scale=1.0)
    rng = np.random.default_rng(0)

    def measured(condition: Condition):
        return reference.fitness(life.render(background, condition, rng))

    low, high = camera_range.exposure_stops
    dark = -float(measured(Condition(stops=low)).exposure_stops) + FIT_MARGIN_STOPS
    bright = float(measured(Condition(stops=high)).exposure_stops) + FIT_MARGIN_STOPS
    sharpness = BLURRED_SHARPNESS
    if camera_range.blurred > 0 and camera_range.blur_sigma_px > 0:
        sharpness = float(measured(Condition(blur_sigma_px=camera_range.blur_sigma_px)).sharpness) \
            * FIT_SHARPNESS_MARGIN
    casts = [measured(Condition(gains=tuple(float(gain) * (2.0 ** tint if channel == 1 else 1.0)
                                            for channel, gain in enumerate(white_balance_gains(mired)))))
             .colour_cast_stops
             for mired in (-camera_range.white_balance_mired, camera_range.white_balance_mired)
             for tint in (-camera_range.tint_stops, camera_range.tint_stops)]
    cast = max((float(value) for value in casts if value is not None), default=0.0) + FIT_CAST_MARGIN_STOPS
    return FitRange(dark_stops=round(max(DARK_STOPS, dark), 3), overexposed_stops=round(max(OVEREXPOSED_STOPS,
                                                                                              bright), 3),
                    blurred_sharpness=round(min(BLURRED_SHARPNESS, sharpness), 3),
                    colour_cast_stops=round(max(COLOUR_CAST_STOPS, cast), 3), monochrome=camera_range.night_ir > 0)
