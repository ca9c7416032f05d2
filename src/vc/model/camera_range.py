"""What the camera will see besides its one image: every training window's composite (background and people
together) varied over the camera's life — exposure, white balance, IR night mode, gain noise, weather, blur,
compression.

A bundle learned from one background exposed one way took anything that departed from that look for people: two
stops less light, a white-balance drift, the IR night mode each made it invent tens of people on the empty scene
(issue 62). A camera in service meets all of these every day, so the composite varies over them, background and
people alike, and the network learns that a person is a shape, not a departure from the background's colour.

Why on the training windows and not in the render: the variation acts on the whole composite, which the dataset
stores already encoded; decoding it through the scene's camera response gives the linear light back (to an 8-bit
level), so each draw of a window gets its own condition at a fraction of a millisecond, where a render-time draw
would fix one condition per stored sample and cost a re-render to change a range. The order is the light's, from
the scene through the air and the lens to the sensor, in linear light (:meth:`CameraLife.apply`):

1. **precipitation** — rain or snow between the scene and the camera: bright particles, streaked by their fall
   during the exposure, over :attr:`CameraRange.precipitation` of the draws;
2. **veil** — fog, haze, or the glare of a dirty dome in the sun: the scene's light seen through a transmission
   ``t`` (down to :attr:`CameraRange.veil_transmission`) and an airlight filling the rest, patchy across the view
   (Koschmieder's model, ``t L + (1 - t) A``), over :attr:`CameraRange.veiled` of the draws;
3. **night mode** — IR monochrome: every channel becomes one mix of the three, its weights drawn (materials reflect
   near-infrared unlike visible light; the mix stands in for that), on :attr:`CameraRange.night_ir` of the draws;
4. **white balance** — a residual cast the camera's white balance leaves: the light's colour temperature off the
   balanced one by up to :attr:`CameraRange.white_balance_mired` (Planckian locus, colour-science) and a green tint;
5. **blur** — one of a wet or dirty lens (a Gaussian of up to :attr:`CameraRange.blur_sigma_px`), focus drift (a
   disc of radius up to :attr:`CameraRange.defocus_px`: an IR-switching camera refocuses) and a camera shaking on its
   pole in the wind (a line up to :attr:`CameraRange.shake_px` long), in camera pixels;
6. **exposure and gain** — the light changes by ``s`` stops within :attr:`CameraRange.exposure_stops`; below the
   scene's light the sensor collects fewer photons, so the shot and read noise of that darker exposure (the frames'
   measured noise model) is added, and the camera's gain then recovers part of the brightness, amplifying that
   noise: the dusk frame that is dark, or bright and grainy. On :attr:`CameraRange.noisy` of the draws the camera
   runs at a high gain besides (a night scene, a cheap sensor, noise reduction off): shot and read noise up to
   :attr:`CameraRange.gain_noise` of the code range at mid-grey;
7. **encoding** — the camera response back to 8 bits, then block compression at a quality drawn from
   :attr:`CameraRange.jpeg_quality` on a share of the draws.

A share :attr:`CameraRange.varied` of the draws is varied; the rest keep the look the scene was calibrated to, which
stays the common case. Geometry is not varied: a nudged camera moves the picture by a few pixels, which the fully
convolutional network already meets as the training windows' random positions (a window is cut anywhere), and a roll
of a fraction of a degree the networks hold; a larger move or roll the runtime registers and undoes
(docs/decisions/0026-camera-roll.md).
Every draw is a pure function of the stream's generator, as the rest of a training item is.
"""

from __future__ import annotations

import math
import time
from collections.abc import Sequence
from dataclasses import asdict, dataclass

import colour
import cv2
import numpy as np

from vc.calibration.compression import jpeg_round_trip
from vc.calibration.noise import NoiseModel
from vc.calibration.response import Response
from vc.deploy.fitness import (
    BLURRED_SHARPNESS,
    CHANGED_AGREEMENT,
    COLOUR_CAST_STOPS,
    DARK_STOPS,
    NOISE_CODES,
    OVEREXPOSED_STOPS,
    VEIL_SHARE,
    FitRange,
    SceneReference,
)

#: The colour temperature a camera's white balance is taken to be set for (K): sRGB's white, D65's.
BALANCED_CCT_K = 6504.0
#: Side of the bank of unit noise a stream draws once and crops per draw (drawing fresh noise per window cost 1.5 ms
#: of the loader's time, which is the training step's on a CPU).
NOISE_BANK_PX = 512
#: The code the gain noise is set at (mid-grey).
MID_GREY_CODE = 128
#: Draws the cost of the variation is timed on (the mean is reported).
COST_REPEATS = 20
#: A frame is fit up to this many stops beyond the exposures the range renders, as the scene fitness reads them.
FIT_MARGIN_STOPS = 0.25
#: ... down to this share of the sharpness of the most blur it renders ...
FIT_SHARPNESS_MARGIN = 0.8
#: ... and up to this much more colour cast than its strongest white-balance error ...
FIT_CAST_MARGIN_STOPS = 0.1
#: ... this much more noise than its highest gain (its networks keep 0.9 of their clean AP50 to about 1.6 times it, with
#: no false people: docs/decisions/0022-noise-beyond-the-range.md) ...
FIT_NOISE_MARGIN = 1.65
#: ... this much more of the light a veil's than its thickest ...
FIT_VEIL_MARGIN = 0.1
#: ... and down to this share of the agreement with the background its blur, noise, veil and snow leave, though
#: never below :data:`FIT_AGREEMENT_FLOOR`: another camera's view matches 0.1 at most.
FIT_AGREEMENT_MARGIN = 0.9
FIT_AGREEMENT_FLOOR = 0.3


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
    #: Share of varied draws blurred, each by one of: a wet or dirty lens (Gaussian, sigma up to ``blur_sigma_px``),
    #: focus drift (a disc of radius up to ``defocus_px``: an IR-switching lens refocuses, a dome fogs) and a camera
    #: shaking on its pole in the wind (a line up to ``shake_px`` long, any direction), in camera pixels. 0 turns a
    #: kind off.
    blurred: float = 0.3
    blur_sigma_px: float = 2.0
    defocus_px: float = 6.0
    shake_px: float = 24.0
    #: Share of varied draws at a high sensor gain besides the exposure's own noise (a night scene, a small sensor,
    #: noise reduction off), and the most of it: the noise's standard deviation at mid-grey (code 128) as a share of
    #: the code range, to first order (0.2: 51 codes, a signal-to-noise ratio of 2.5 there).
    noisy: float = 0.25
    gain_noise: float = 0.2
    #: Share of varied draws seen through a veil (fog, haze, a dirty dome's glare), and the least transmission left
    #: of the scene's light (0.25: a fog a few tens of metres deep, most of the view's contrast gone).
    veiled: float = 0.2
    veil_transmission: float = 0.25
    #: Share of varied draws with rain or snow falling between the scene and the camera.
    precipitation: float = 0.1
    #: Share of varied draws block-compressed, at a JPEG quality within this range (a stream's bitrate dropping).
    compressed: float = 0.25
    jpeg_quality: tuple[int, int] = (30, 90)
    #: Share of the draws varied at all; the rest keep the look the scene was calibrated to.
    varied: float = 0.75

    def __post_init__(self) -> None:
        low, high = self.exposure_stops
        if not low <= 0.0 <= high:
            raise ValueError(f"exposure_stops {self.exposure_stops} must hold 0 (the scene's own exposure)")
        for name in ("night_ir", "blurred", "noisy", "veiled", "precipitation", "compressed", "varied"):
            if not 0.0 <= getattr(self, name) <= 1.0:
                raise ValueError(f"{name} is a share of draws, between 0 and 1")
        for name in ("white_balance_mired", "tint_stops", "blur_sigma_px", "defocus_px", "shake_px", "gain_noise"):
            if getattr(self, name) < 0:
                raise ValueError(f"{name} is a range from nothing: not negative")
        if not 0.0 < self.veil_transmission <= 1.0:
            raise ValueError(f"veil_transmission {self.veil_transmission} is the share of the light left: in (0, 1]")
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


def disc_kernel(radius: float) -> np.ndarray:
    """A defocused lens's point spread: a disc of ``radius`` pixels, its edge anti-aliased, summing to 1."""
    half = int(math.ceil(radius))
    ys, xs = np.mgrid[-half:half + 1, -half:half + 1]
    kernel = np.clip(radius + 0.5 - np.hypot(xs, ys), 0.0, 1.0).astype(np.float32)
    return kernel / kernel.sum()


def line_kernel(length: float, angle_deg: float) -> np.ndarray:
    """A straight motion's point spread: a line ``length`` pixels long at ``angle_deg`` from the x axis (y down),
    sampled finely and splatted bilinearly, summing to 1."""
    half = int(math.ceil(length / 2.0)) + 1
    kernel = np.zeros((2 * half + 1, 2 * half + 1), np.float32)
    steps = np.linspace(-length / 2.0, length / 2.0, max(2, int(4 * length) + 1))
    angle = math.radians(angle_deg)
    xs, ys = half + steps * math.cos(angle), half + steps * math.sin(angle)
    x0, y0 = np.floor(xs).astype(int), np.floor(ys).astype(int)
    fx, fy = (xs - x0).astype(np.float32), (ys - y0).astype(np.float32)
    for dx, dy, weight in ((0, 0, (1 - fx) * (1 - fy)), (1, 0, fx * (1 - fy)), (0, 1, (1 - fx) * fy),
                           (1, 1, fx * fy)):
        np.add.at(kernel, (y0 + dy, x0 + dx), weight)
    return kernel / kernel.sum()


@dataclass(frozen=True)
class Condition:
    """One draw's camera condition (what :meth:`CameraLife.apply` did to a window); sizes in window pixels."""

    stops: float = 0.0
    recovered_stops: float = 0.0  # of the light lost, what the camera's gain brought back
    gains: tuple[float, float, float] = (1.0, 1.0, 1.0)
    ir_mix: tuple[float, float, float] | None = None
    blur_sigma_px: float = 0.0  # a wet lens: Gaussian sigma
    defocus_px: float = 0.0  # focus drift: the disc's radius
    shake_px: float = 0.0  # a shaking camera: the line's length ...
    shake_angle_deg: float = 0.0  # ... and direction
    gain_noise: float = 0.0  # the high gain's noise at mid-grey, share of the code range
    shot_share: float = 1.0  # ... of its variance there, the share that grows with the light (the rest is read noise)
    veil_transmission: float = 1.0  # of the scene's light, the share the veil lets through ...
    airlight: float = 0.0  # ... and the light that fills the rest, over the window's mean luminance
    veil_patchiness: float = 0.0  # how much the airlight varies across the view (relative)
    precipitation: tuple[float, float, float, float, float] | None = None  # density, flake sigma, streak length,
    # angle from the vertical (degrees), opacity
    jpeg_quality: int | None = None

    @property
    def unchanged(self) -> bool:
        return self == Condition()


#: Rain and snow: particles per window pixel, flake sigma and streak length (camera pixels), angle from the vertical
#: (degrees), opacity. Drizzle to a heavy snowfall; fast rain streaks long and faint, snow short and bright.
PRECIPITATION_DENSITY = (0.0005, 0.006)
PRECIPITATION_FLAKE_PX = (0.0, 1.5)
PRECIPITATION_STREAK_PX = (1.0, 20.0)
PRECIPITATION_ANGLE_DEG = 30.0
PRECIPITATION_OPACITY = (0.3, 1.0)
#: The airlight over the window's mean luminance: 1 dims the contrast toward the mean (haze), 3 lifts it toward a
#: bright sky (fog in daylight, a dome's glare); the light is capped at the sensor's white.
AIRLIGHT_RATIO = (1.0, 3.0)
#: The veil's airlight varies across the view by up to this much (relative): fog is patchy, glare falls off.
VEIL_PATCHINESS = 0.3
#: Cells of the veil's patch pattern across a window's long side.
VEIL_PATCH_CELLS = 4
#: The particles' brightness over the window's mean luminance (lit by the sky, brighter than the ground).
PARTICLE_RATIO = 2.5


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
        codes = response.decode(np.array([MID_GREY_CODE, MID_GREY_CODE + 1], np.uint8))
        #: Mid-grey's linear light, and the linear light of one code there (the gain noise is set in codes).
        self._mid_grey, self._code_step = float(codes[0]), float(codes[1] - codes[0])

    def draw(self, rng: np.random.Generator) -> Condition:
        """A condition from the ranges (the unchanged one for the share not varied)."""
        spec, scale = self.range, self.region_scale
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
        blur: dict[str, float] = {}
        kinds = [(name, size) for name, size in (("blur_sigma_px", spec.blur_sigma_px),
                                                 ("defocus_px", spec.defocus_px), ("shake_px", spec.shake_px))
                 if size > 0]
        if rng.random() < spec.blurred and kinds:
            name, size = kinds[int(rng.integers(len(kinds)))]
            blur[name] = float(rng.uniform(0.0, size)) * scale
            if name == "shake_px":
                blur["shake_angle_deg"] = float(rng.uniform(0.0, 180.0))
        noise: dict[str, float] = {}
        if rng.random() < spec.noisy and spec.gain_noise > 0:
            noise = {"gain_noise": float(rng.uniform(0.0, spec.gain_noise)), "shot_share": float(rng.uniform(0.5, 1))}
        veil: dict[str, float] = {}
        if rng.random() < spec.veiled and spec.veil_transmission < 1:
            veil = {"veil_transmission": float(rng.uniform(spec.veil_transmission, 1.0)),
                    "airlight": float(rng.uniform(*AIRLIGHT_RATIO)),
                    "veil_patchiness": float(rng.uniform(0.0, VEIL_PATCHINESS))}
        precipitation = None
        if rng.random() < spec.precipitation:
            precipitation = (float(rng.uniform(*PRECIPITATION_DENSITY)),
                             float(rng.uniform(*PRECIPITATION_FLAKE_PX)) * scale,
                             float(rng.uniform(*PRECIPITATION_STREAK_PX)) * scale,
                             float(rng.uniform(-PRECIPITATION_ANGLE_DEG, PRECIPITATION_ANGLE_DEG)),
                             float(rng.uniform(*PRECIPITATION_OPACITY)))
        quality = int(rng.integers(spec.jpeg_quality[0], spec.jpeg_quality[1] + 1)) \
            if rng.random() < spec.compressed else None
        return Condition(stops, recovered, gains, ir_mix, **blur, **noise, **veil, precipitation=precipitation,
                         jpeg_quality=quality)

    def apply(self, image: np.ndarray, rng: np.random.Generator) -> np.ndarray:
        """``image`` ((H, W, 3) uint8, the camera's encoding) under a condition drawn from ``rng``, uint8."""
        condition = self.draw(rng)
        return image if condition.unchanged else self.render(image, condition, rng)

    def render(self, image: np.ndarray, condition: Condition, rng: np.random.Generator) -> np.ndarray:
        """``image`` under ``condition`` (module docstring, steps 1-7)."""
        linear = self.response.decode(image)
        if condition.precipitation is not None:
            linear = self._precipitation(linear, condition.precipitation, rng)
        if condition.veil_transmission < 1.0:
            linear = self._veil(linear, condition, rng)
        if condition.ir_mix is not None:
            mono = linear @ np.asarray(condition.ir_mix, np.float32)
            linear = np.repeat(mono[..., None], 3, axis=2)
        else:
            linear = linear * np.asarray(condition.gains, np.float32)
        if condition.blur_sigma_px > 0:
            linear = cv2.GaussianBlur(linear, (0, 0), condition.blur_sigma_px)
        if condition.defocus_px > 0:
            linear = cv2.filter2D(linear, -1, disc_kernel(condition.defocus_px), borderType=cv2.BORDER_REFLECT)
        if condition.shake_px > 0:
            linear = cv2.filter2D(linear, -1, line_kernel(condition.shake_px, condition.shake_angle_deg),
                                  borderType=cv2.BORDER_REFLECT)
        if condition.stops != 0.0:
            light = np.float32(2.0 ** condition.stops)
            linear = linear * light
            if condition.stops < 0:
                linear = linear + self._darker_exposure_noise(linear, light, rng)
                linear *= np.float32(2.0 ** condition.recovered_stops)
        if condition.gain_noise > 0:
            linear = linear + self._gain_noise(linear, condition, rng)
        encoded = self.response.encode(linear)
        if condition.jpeg_quality is not None:
            encoded = jpeg_round_trip(encoded, condition.jpeg_quality, chroma_subsampling=True)
        return encoded

    def _precipitation(self, linear: np.ndarray, precipitation: tuple[float, float, float, float, float],
                       rng: np.random.Generator) -> np.ndarray:
        """Rain or snow: particles at ``density`` per pixel, flakes of Gaussian ``flake`` sigma (peak 1), streaked
        along their fall (a line ``streak`` long, ``angle`` from the vertical, its light spread along it), covering
        the scene by up to ``opacity`` with the light of a particle lit by the sky (:data:`PARTICLE_RATIO`)."""
        density, flake, streak, angle, opacity = precipitation
        height, width = linear.shape[:2]
        particles = (rng.random((height, width), dtype=np.float32) < np.float32(density)).astype(np.float32)
        if flake > 0.3:
            particles = cv2.GaussianBlur(particles, (0, 0), flake) * np.float32(2.0 * math.pi * flake * flake)
        streaked = cv2.filter2D(particles, -1, line_kernel(streak, 90.0 + angle), borderType=cv2.BORDER_REFLECT)
        cover = np.clip(streaked * np.float32(opacity), 0.0, 1.0)[..., None]
        light = np.float32(min(PARTICLE_RATIO * float(linear.mean()), 1.0))
        return linear * (1.0 - cover) + light * cover

    def _veil(self, linear: np.ndarray, condition: Condition, rng: np.random.Generator) -> np.ndarray:
        """Koschmieder's veil: ``t L + (1 - t) A``, the airlight ``A`` a ratio of the window's mean luminance,
        varied across the view by a smooth random pattern (:data:`VEIL_PATCH_CELLS`)."""
        height, width = linear.shape[:2]
        pattern = rng.standard_normal((VEIL_PATCH_CELLS + 1, VEIL_PATCH_CELLS + 1)).astype(np.float32)
        pattern = cv2.resize(pattern, (width, height), interpolation=cv2.INTER_CUBIC)
        field = np.clip(1.0 + np.float32(condition.veil_patchiness) * pattern, 0.0, None)
        airlight = np.float32(min(condition.airlight * float(linear.mean()), 1.0))
        transmission = np.float32(condition.veil_transmission)
        return linear * transmission + ((1.0 - transmission) * airlight * field)[..., None]

    def _gain_noise(self, linear: np.ndarray, condition: Condition, rng: np.random.Generator) -> np.ndarray:
        """A high gain's shot and read noise: variance ``k x + r^2`` in linear light, set so that its standard
        deviation at mid-grey is ``gain_noise`` of the code range, ``shot_share`` of that variance growing with the
        light."""
        sigma = condition.gain_noise * 255.0 * self._code_step
        variance = sigma * sigma
        shot = np.float32(condition.shot_share * variance / self._mid_grey)
        read = np.float32((1.0 - condition.shot_share) * variance)
        height, width = linear.shape[:2]
        return self._unit_noise(height, width, rng) * np.sqrt(shot * np.clip(linear, 0.0, None) + read)

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
        ("high gain", spec.noisy > 0 and spec.gain_noise > 0,
         f"{spec.noisy:.0%} of the varied windows with shot and read noise up to {spec.gain_noise:.2f} of the code "
         "range at mid-grey (a night scene, noise reduction off)"),
        ("veil", spec.veiled > 0 and spec.veil_transmission < 1,
         f"{spec.veiled:.0%} of the varied windows through fog, haze or a dome's glare, down to "
         f"{spec.veil_transmission:.0%} of the light"),
        ("rain and snow", spec.precipitation > 0, f"{spec.precipitation:.0%} of the varied windows"),
        ("blur", spec.blurred > 0 and max(spec.blur_sigma_px, spec.defocus_px, spec.shake_px) > 0,
         f"{spec.blurred:.0%} of the varied windows blurred: a wet lens up to sigma {spec.blur_sigma_px:.1f}, "
         f"focus drift up to radius {spec.defocus_px:.1f}, shake up to {spec.shake_px:.0f} camera px"),
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
                 response: Response, frames: Sequence[np.ndarray] = ()) -> FitRange:
    """What a bundle compiled over ``camera_range`` sees, as the scene fitness reads frames: the ``background``
    ((H, W, 3) uint8, the reference's) rendered at the range's ends — its darkest and brightest exposures, each blur
    at its most, its strongest white-balance casts, its most gain noise, its veils (the thickest and half as thick,
    each airlight, even and patchy), its densest snow — and measured against ``reference``, with a margin beyond
    each (:data:`FIT_MARGIN_STOPS`, :data:`FIT_SHARPNESS_MARGIN`, :data:`FIT_CAST_MARGIN_STOPS`,
    :data:`FIT_NOISE_MARGIN`, :data:`FIT_VEIL_MARGIN`, :data:`FIT_AGREEMENT_MARGIN`); never tighter than the
    background's own look (:class:`FitRange`'s defaults), and
    the agreement never below :data:`FIT_AGREEMENT_FLOOR`. Monochrome frames are fit when the range has a night
    mode. Measured, not derived, because the fitness reads through coarse cells and clipping: the measurement is
    what a frame at the range's end will read. The range is the background's light varied; a camera's own ``frames``
    (its video) drift from its median background (TUD-Stadtmitte's by up to 0.37 stop), and the exposure bounds
    widen by their drift either way."""
    if camera_range is None:
        return FitRange()
    drifts = [float(reference.fitness(frame).exposure_stops) for frame in frames]
    darker, brighter = max(0.0, -min(drifts, default=0.0)), max(0.0, max(drifts, default=0.0))
    spec = camera_range
    life = CameraLife(spec, response, NoiseModel(0.0, 0.0), region_scale=1.0)
    rng = np.random.default_rng(0)

    def measured(condition: Condition):
        return reference.fitness(life.render(background, condition, rng))

    low, high = spec.exposure_stops
    dark = -float(measured(Condition(stops=low)).exposure_stops) + FIT_MARGIN_STOPS + darker
    bright = float(measured(Condition(stops=high)).exposure_stops) + FIT_MARGIN_STOPS + brighter
    casts = [measured(Condition(gains=tuple(float(gain) * (2.0 ** tint if channel == 1 else 1.0)
                                            for channel, gain in enumerate(white_balance_gains(mired)))))
             .colour_cast_stops
             for mired in (-spec.white_balance_mired, spec.white_balance_mired)
             for tint in (-spec.tint_stops, spec.tint_stops)]
    cast = max((float(value) for value in casts if value is not None), default=0.0) + FIT_CAST_MARGIN_STOPS
    blurs = [Condition(**{name: size}) for name, size in (("blur_sigma_px", spec.blur_sigma_px),
                                                          ("defocus_px", spec.defocus_px),
                                                          ("shake_px", spec.shake_px)) if spec.blurred > 0 and size > 0]
    blurred = [measured(condition) for condition in blurs]
    sharpness = min((float(fitness.sharpness) for fitness in blurred), default=BLURRED_SHARPNESS / FIT_SHARPNESS_MARGIN)
    noisiest = measured(Condition(gain_noise=spec.gain_noise, shot_share=0.75)) \
        if spec.noisy > 0 and spec.gain_noise > 0 else None
    # the veil's share is read through clipping and the fit's bands, so not always largest at the thickest veil
    # (TUD-Stadtmitte's bright ground clips under its brightest airlight and reads no veil): its ends and midpoints,
    # even and patchy
    veiled = [measured(Condition(veil_transmission=transmission, airlight=airlight, veil_patchiness=patchiness))
              for transmission in (spec.veil_transmission, (1.0 + spec.veil_transmission) / 2)
              for airlight in (AIRLIGHT_RATIO[0], sum(AIRLIGHT_RATIO) / 2, AIRLIGHT_RATIO[1])
              for patchiness in (0.0, VEIL_PATCHINESS)] \
        if spec.veiled > 0 and spec.veil_transmission < 1 else []
    snowing = measured(Condition(precipitation=(PRECIPITATION_DENSITY[1], PRECIPITATION_FLAKE_PX[1],
                                                PRECIPITATION_STREAK_PX[0], 0.0, PRECIPITATION_OPACITY[1]))) \
        if spec.precipitation > 0 else None
    ends = [fitness for fitness in (*blurred, noisiest, *veiled, snowing) if fitness is not None]
    agreement = min(float(fitness.matching) for fitness in ends) * FIT_AGREEMENT_MARGIN if ends \
        else CHANGED_AGREEMENT
    return FitRange(dark_stops=round(max(DARK_STOPS, dark), 3),
                    overexposed_stops=round(max(OVEREXPOSED_STOPS, bright), 3),
                    blurred_sharpness=round(min(BLURRED_SHARPNESS, sharpness * FIT_SHARPNESS_MARGIN), 3),
                    colour_cast_stops=round(max(COLOUR_CAST_STOPS, cast), 3), monochrome=spec.night_ir > 0,
                    veil_share=round(max(VEIL_SHARE, max((fitness.veil + FIT_VEIL_MARGIN for fitness in veiled),
                                                         default=0.0)), 3),
                    noise_codes=round(max(NOISE_CODES, noisiest.noise_codes * FIT_NOISE_MARGIN if noisiest else 0.0),
                                      2),
                    changed_agreement=round(min(CHANGED_AGREEMENT, max(FIT_AGREEMENT_FLOOR, agreement)), 3))
