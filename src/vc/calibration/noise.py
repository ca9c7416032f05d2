"""Signal-dependent sensor noise: measured on a camera's images, added to a synthetic composite.

Units and domains, stated once:

* The model lives in **linear light** on [0, 1] (what :meth:`vc.calibration.response.Response.decode` returns):
  a pixel of linear value ``I`` carries noise of variance ``shot * I + read**2`` — photon (shot) noise grows
  with the signal, read noise does not. It is added before the response encodes the composite, as in a camera.
* Measurements are taken on the **encoded** 8-bit image, where the noise is ``f'(I)`` times the linear noise
  (``f`` the response curve), and carried back to linear light by the decoding curve's slope at each level.
* 8-bit rounding adds a variance of 1/12 level² to every measurement (for noise above a fraction of a level);
  it is subtracted, because encoding the composite rounds it again.
* All three channels are pooled: each (block, channel) or (pixel, channel) is one measurement at that
  channel's level; a camera's channels share one noise model here.
"""

from __future__ import annotations

from collections.abc import Iterator, Sequence
from dataclasses import asdict, dataclass

import cv2
import numpy as np
from scipy.optimize import least_squares

from vc.calibration.response import Response

#: Side of the square blocks an image is measured in (pixels).
BLOCK = 16
#: Intensity bins (equal steps of the encoded value) the measurements are grouped in before fitting.
BINS = 16
#: An image's bin is measured on its flattest blocks, this share of them ...
FLAT_SHARE = 0.25
#: ... and at least this many; a bin with fewer blocks is left out.
MIN_BLOCKS_PER_BIN = 6
#: A video's bin enters the fit with at least this many static (pixel, channel) measurements.
MIN_PIXELS_PER_BIN = 200
#: Variance 8-bit rounding adds to a measurement (level²): a uniform error on [-1/2, 1/2].
QUANTISATION_VARIANCE = 1.0 / 12.0
#: Relative error of the model itself (real sensors are not exactly shot + read), added to a bin's standard
#: error, so that millions of video pixels do not make one bin's few percent a hundred sigmas.
MODEL_ERROR = 0.05
#: A video pixel is static when it stays within this many of its level's noise sigmas of the background ...
STATIC_SIGMAS = 5.0
#: ... plus this many 8-bit levels (the background's own rounding and slight drifts).
STATIC_MARGIN = 1.0

#: Immerkær's noise operator ("Fast noise variance estimation", 1996): the difference of two Laplacians, zero
#: on any surface that is quadratic along x or along y, so smooth shading does not count as noise. Its response
#: to white noise of sigma ``s`` has sigma ``6 s``.
_HIGH_PASS = np.array([[1, -2, 1], [-2, 4, -2], [1, -2, 1]], np.float32)
_HIGH_PASS_GAIN = 6.0
#: Mean absolute value of a zero-mean Gaussian, over its sigma.
_MEAN_ABS_PER_SIGMA = np.sqrt(2.0 / np.pi)


@dataclass(frozen=True)
class NoiseModel:
    """Noise of variance ``shot * I + read**2`` at linear value ``I`` (linear light on [0, 1])."""

    shot: float
    read: float

    def variance(self, linear: np.ndarray) -> np.ndarray:
        """Noise variance at each linear value (negative values, e.g. of an already noisy pixel, count as 0)."""
        return self.shot * np.clip(np.asarray(linear, np.float32), 0.0, None) + np.float32(self.read**2)

    def sigma(self, linear: np.ndarray) -> np.ndarray:
        return np.sqrt(self.variance(linear))

    def apply(self, linear: np.ndarray, rng: np.random.Generator, keep_variance: np.ndarray | None = None,
              unit: np.ndarray | None = None) -> np.ndarray:
        """``linear`` plus zero-mean Gaussian noise of the model's variance, less ``keep_variance`` (variance the
        pixels already carry, e.g. a photograph's own noise; broadcast against ``linear``), never below zero.
        ``unit`` is the unit-variance noise to scale (default: drawn from ``rng``), for noise whose spatial
        correlation is made elsewhere, e.g. drawn at the camera's resolution and resized with the image.
        float32, not clipped: the camera response clips when it encodes."""
        linear = np.asarray(linear, np.float32)
        variance = self.variance(linear)
        if keep_variance is not None:
            variance = np.clip(variance - np.asarray(keep_variance, np.float32), 0.0, None)
        if unit is None:
            unit = rng.standard_normal(linear.shape, dtype=np.float32)
        return linear + unit * np.sqrt(variance)

    def to_dict(self) -> dict:
        return asdict(self)


@dataclass(frozen=True)
class NoiseEstimate:
    """A fitted :class:`NoiseModel` and what it rests on: ``samples`` (block, channel) measurements of one image
    or (pixel, channel) measurements of a video; 0 when nothing could be measured (the model is then zero)."""

    model: NoiseModel
    sigma_at_mid_grey_8bit: float  # the model's noise at encoded value 0.5, in 8-bit levels
    samples: int
    method: str  # "flat blocks" or "temporal variance"

    def to_dict(self) -> dict:
        return {"model": self.model.to_dict(), "sigma_at_mid_grey_8bit": self.sigma_at_mid_grey_8bit,
                "samples": self.samples, "method": self.method}


def _decode_slope(response: Response, encoded: np.ndarray) -> np.ndarray:
    """d(linear)/d(encoded) at encoded values on [0, 1] (central difference, one-sided at the ends)."""
    step = 1e-3
    low = np.clip(encoded - step, 0.0, 1.0)
    high = np.clip(encoded + step, 0.0, 1.0)
    return (response.decode(high) - response.decode(low)) / (high - low)


def _levels(image: np.ndarray, name: str) -> np.ndarray:
    """(H, W, C) float32 in 8-bit levels from a uint8 image or a float one on [0, 1]."""
    image = np.asarray(image)
    if image.ndim == 2:
        image = image[..., None]
    if image.ndim != 3:
        raise ValueError(f"{name} must be (H, W) or (H, W, C), got shape {image.shape}")
    if image.dtype == np.uint8:
        return image.astype(np.float32)
    if not np.issubdtype(image.dtype, np.floating):
        raise ValueError(f"{name} must be uint8 or float on [0, 1], got {image.dtype}")
    if not np.isfinite(image).all():
        raise ValueError(f"{name} contains NaN or infinite values")
    return (image * 255.0).astype(np.float32)


def _fit(response: Response, encoded: np.ndarray, variance: np.ndarray, error: np.ndarray) -> NoiseModel:
    """Non-negative ``shot``, ``read`` with ``shot * I + read**2`` through bins at ``encoded`` levels with linear
    ``variance`` known to ``error`` (standard error).

    Residuals in units of each bin's error (plus :data:`MODEL_ERROR`) under a soft-L1 loss: a bin that texture
    or motion threw off does not drag the fit. Bins at a single level cannot tell shot from read noise: the
    noise is then taken as constant."""
    intensity = response.decode(encoded).astype(np.float64)
    # A floor of a twentieth of a level keeps exactly measured bins (noiseless ones) from infinite weight.
    floor = (0.05 / 255.0 * _decode_slope(response, encoded)) ** 2
    scale = np.sqrt(error**2 + (MODEL_ERROR * variance) ** 2) + floor
    if np.ptp(encoded) < 2.0 / BINS:
        read_variance = max(float(np.average(variance, weights=scale**-2)), 0.0)
        return NoiseModel(0.0, float(np.sqrt(read_variance)))
    design = np.stack([intensity, np.ones_like(intensity)], axis=1) / scale[:, None]
    target = variance / scale
    start = np.array([0.0, max(float(np.median(variance)), 0.0)])
    fit = least_squares(lambda x: design @ x - target, start, bounds=(0.0, np.inf), loss="soft_l1", x_scale="jac")
    shot, read_variance = (max(float(value), 0.0) for value in fit.x)
    return NoiseModel(shot, float(np.sqrt(read_variance)))


def _from_bins(response: Response, method: str, bins: list[tuple[np.ndarray, np.ndarray]]) -> NoiseEstimate:
    """The estimate from the measurements each intensity bin keeps: (encoded levels on [0, 1], linear noise
    variances). A bin's variance is their mean, known to its standard error."""
    if not bins:
        return _nothing(method)
    encoded = np.array([levels.mean() for levels, _ in bins])
    variance = np.array([values.mean() for _, values in bins])
    error = np.array([values.std(ddof=1) / np.sqrt(values.size) for _, values in bins])
    model = _fit(response, encoded, variance, error)
    mid = np.array([0.5])
    sigma_8bit = float(model.sigma(response.decode(mid))[0] / _decode_slope(response, mid)[0] * 255.0)
    return NoiseEstimate(model, sigma_8bit, sum(values.size for _, values in bins), method)


def _nothing(method: str) -> NoiseEstimate:
    return NoiseEstimate(NoiseModel(0.0, 0.0), 0.0, 0, method)


def _halve(levels: np.ndarray) -> np.ndarray:
    """The image at half resolution: exact 2 x 2 means (an odd last row or column is dropped)."""
    height, width, channels = levels.shape[0] // 2, levels.shape[1] // 2, levels.shape[2]
    return levels[: 2 * height, : 2 * width].reshape(height, 2, width, 2, channels).mean(axis=(1, 3))


def _high_pass_variance(levels: np.ndarray, block: int, rows: int, cols: int) -> np.ndarray:
    """Immerkær's noise variance (level²) of each block and channel: (rows * cols, channels). Output (i, j) of
    the valid high-pass sees pixels i..i+2, j..j+2, so a block of ``block`` outputs sees ``block + 2`` pixels."""
    height, width, channels = levels.shape
    response = np.abs(cv2.filter2D(levels, cv2.CV_32F, _HIGH_PASS)).reshape(height, width, channels)[1:-1, 1:-1]
    tiles = response[: rows * block, : cols * block].reshape(rows, block, cols, block, channels)
    return (tiles.mean(axis=(1, 3)).reshape(rows * cols, channels) / (_HIGH_PASS_GAIN * _MEAN_ABS_PER_SIGMA)) ** 2


def estimate_noise_image(image: np.ndarray, response: Response) -> NoiseEstimate:
    """Noise level function of one image (uint8, or float on [0, 1]; encoded by ``response``), from flat blocks.

    Each 16 x 16 block and channel is measured with Immerkær's operator (its mean absolute response: unlike a
    median it stays continuous on 8-bit data at the one-to-two-level noise that matters; the wavelet MAD of
    ``skimage.restoration.estimate_sigma`` needs PyWavelets, which is not installed, and one call per block) on
    the image and on its 2 x 2 and 4 x 4 means, which give variances ``V1``, ``V2``, ``V4``:

    * white noise keeps a quarter of its variance per halving; the texture of natural scenes, whose spectrum
      falls as 1/f², has about as much in one octave as in the next. ``4/3 (V1 - V2)`` keeps the noise and
      cancels such texture (a render's fine texture would otherwise read as a level of noise);
    * the flattest blocks are those with the least structure two octaves up (``V4``, which noise hardly
      reaches): edges and coarse texture, where the octaves differ most, are left out, and choosing by a scale
      the estimate does not use does not bias it.

    Blocks touching a clipped pixel (0 or 255 in any channel) are left out — saturation has no noise — and so
    are blocks with no high-pass response at all (a painted or synthetic area: no noise to measure). Per
    intensity bin the flattest :data:`FLAT_SHARE` of the blocks are averaged; the model is fitted through the
    bins (see :func:`_fit`)."""
    method = "flat blocks"
    levels = _levels(image, "image")
    half = _halve(levels)
    quarter = _halve(half)
    rows = min((levels.shape[0] - 2) // BLOCK, (half.shape[0] - 2) // (BLOCK // 2), (quarter.shape[0] - 2) // 4)
    cols = min((levels.shape[1] - 2) // BLOCK, (half.shape[1] - 2) // (BLOCK // 2), (quarter.shape[1] - 2) // 4)
    if rows <= 0 or cols <= 0:
        return _nothing(method)

    def per_block(values: np.ndarray, reduce: str) -> np.ndarray:
        tiles = values[1 : 1 + rows * BLOCK, 1 : 1 + cols * BLOCK].reshape(rows, BLOCK, cols, BLOCK, -1)
        return getattr(tiles, reduce)(axis=(1, 3)).reshape(rows * cols, -1)

    full = _high_pass_variance(levels, BLOCK, rows, cols)
    noise = 4.0 / 3.0 * (full - _high_pass_variance(half, BLOCK // 2, rows, cols))
    structure = _high_pass_variance(quarter, BLOCK // 4, rows, cols)
    mean = per_block(levels, "mean") / 255.0
    # The coarsest operator reaches 8 pixels beyond a block's 16.
    clipped = ((levels <= 0.0) | (levels >= 255.0)).any(axis=2).astype(np.uint8)
    clipped = cv2.dilate(clipped, np.ones((19, 19), np.uint8))[..., None]
    usable = (per_block(clipped, "max") == 0) & (full > 0.0)

    noise, structure, mean = noise[usable], structure[usable], mean[usable]
    linear_variance = (noise - QUANTISATION_VARIANCE) * (_decode_slope(response, mean) / 255.0) ** 2
    bin_index = np.minimum((mean * BINS).astype(int), BINS - 1)
    bins = []
    for index in np.unique(bin_index):
        in_bin = np.flatnonzero(bin_index == index)
        if in_bin.size >= MIN_BLOCKS_PER_BIN:
            count = max(MIN_BLOCKS_PER_BIN, int(np.ceil(FLAT_SHARE * in_bin.size)))
            flat = in_bin[np.argsort(structure[in_bin], kind="stable")[:count]]
            bins.append((mean[flat], linear_variance[flat]))
    return _from_bins(response, method, bins)


def estimate_noise_video(frames: Sequence[np.ndarray], background: np.ndarray, response: Response
                         ) -> NoiseEstimate:
    """Noise level function from the temporal variance of static pixels over ``frames`` (uint8, same size as
    ``background``).

    A pixel is static when, in every frame and channel, it stays within :data:`STATIC_SIGMAS` noise sigmas of
    the background (sigmas from the robust spread of frame - background at its level): people walking through
    it are left out. Pixels clipped in any frame are left out. Per (pixel, channel), the variance over the frames
    (less 8-bit rounding) is carried to linear light at its temporal mean; bins average them (temporal variance
    has no texture to reject) and the model is fitted through the bins (see :func:`_fit`)."""
    method = "temporal variance"
    if len(frames) < 3:
        raise ValueError(f"temporal noise needs at least 3 frames, got {len(frames)}")
    reference = _levels(background, "background")
    bin_of = np.minimum((reference / 255.0 * BINS).astype(int), BINS - 1)

    def each_frame() -> Iterator[np.ndarray]:
        for frame in frames:
            levels = _levels(frame, "frame")
            if levels.shape != reference.shape:
                raise ValueError(f"a frame is {levels.shape} but the background is {reference.shape}")
            yield levels

    # Noise sigma of frame - background per background level (MAD over a sparse grid of pixels, all frames).
    sparse_bins = bin_of[::4, ::4]
    sparse_difference = np.stack([levels[::4, ::4] - reference[::4, ::4] for levels in each_frame()])
    spread = np.zeros(BINS, np.float32)
    for index in np.unique(sparse_bins):
        values = sparse_difference[:, sparse_bins == index]
        spread[index] = 1.4826 * np.median(np.abs(values - np.median(values)))  # MAD -> Gaussian sigma
    threshold = STATIC_SIGMAS * spread[bin_of] + STATIC_MARGIN
    static = np.ones(reference.shape[:2], bool)
    for levels in each_frame():
        static &= (np.abs(levels - reference) <= threshold).all(axis=2)
        static &= ((levels > 0.0) & (levels < 255.0)).all(axis=2)
    # Per (pixel, channel) moments over the frames, in float64 (sums of squares of 8-bit levels stay exact).
    total = np.zeros((int(static.sum()), reference.shape[2]))
    total_squares = np.zeros_like(total)
    for levels in each_frame():
        values = levels[static].astype(np.float64)
        total += values
        total_squares += values**2
    mean = total / len(frames)
    variance = (total_squares - len(frames) * mean**2) / (len(frames) - 1) - QUANTISATION_VARIANCE
    mean /= 255.0
    linear_variance = variance / 255.0**2 * _decode_slope(response, mean) ** 2
    bin_index = np.minimum((mean * BINS).astype(int), BINS - 1)
    bins = [(mean[in_bin], linear_variance[in_bin]) for in_bin in (bin_index == index for index in range(BINS))
            if in_bin.sum() >= MIN_PIXELS_PER_BIN]
    return _from_bins(response, method, bins)
