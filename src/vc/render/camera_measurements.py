"""What the scene's own images say about its camera: noise, compression and blur, measured once per render.

The detector will see the camera's *frames*. When the scene gives a video (``video:``), the frames are measured
directly: noise from the temporal variance of static pixels, compression from a few frames. Without one, the
background is the only frame there is, and is measured itself. The background is measured too, because what
it already carries must not be added twice: a temporal-median background (PETS09's) is nearly free of noise and
compression, a single frame is not, a rendered one (the demo's) has neither.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from vc.calibration.compression import JpegEstimate, blockiness, equivalent_quality, estimate_jpeg
from vc.calibration.noise import NoiseEstimate, NoiseModel, estimate_noise_image, estimate_noise_video
from vc.calibration.response import Response
from vc.calibration.sharpness import BlurEstimate, estimate_blur_sigma
from vc.deploy.frames import FrameRange, FrameSource
from vc.errors import InputError
from vc.io import read_image
from vc.scenes.loader import Scene

#: Frames of the scene's video that are measured, spread evenly over its first :data:`VIDEO_SPAN` frames.
VIDEO_FRAMES = 24
VIDEO_SPAN = 240
#: The temporal noise estimate needs at least this many frames.
MIN_VIDEO_FRAMES = 3
#: A video's frames count as visibly block-compressed when their blockiness (8-pixel block boundaries over block
#: interiors, ~1.0 without compression) exceeds the background's, with the frames' noise added, by this much.
MIN_BLOCKINESS_EXCESS = 0.05


@dataclass(frozen=True)
class CameraMeasurements:
    """The camera's noise, compression and blur (see the module docstring)."""

    frames_source: str  # where the frame measurements come from
    frame_noise: NoiseEstimate  # in the frames the detector sees
    background_noise: NoiseEstimate  # already in the background
    compression: JpegEstimate  # of the frames
    background_compression: JpegEstimate  # already in the background
    blur: BlurEstimate  # of the static scene's edges (full-frame pixels)

    def to_dict(self) -> dict:
        return {"frames_source": self.frames_source, "frame_noise": self.frame_noise.to_dict(),
                "background_noise": self.background_noise.to_dict(), "compression": _jpeg_dict(self.compression),
                "background_compression": _jpeg_dict(self.background_compression), "blur": self.blur.to_dict()}


def _jpeg_dict(estimate: JpegEstimate) -> dict:
    return {"quality": estimate.quality, "chroma_subsampling": estimate.chroma_subsampling,
            "evidence": estimate.evidence}


def measured_frames(video: Path) -> FrameRange:
    """Up to :data:`VIDEO_FRAMES` frames spread over the first :data:`VIDEO_SPAN` (fewer in a shorter video): the
    frames measured, which are all a copy of the scene needs of its video
    (``experiments/2026-11-26-compile-time/device/pack_scene_gpu.sh``)."""
    span = min(VIDEO_SPAN, len(FrameSource(video)))
    return FrameRange(1, span, max(1, span // VIDEO_FRAMES))


def video_frames(scene: Scene) -> list[np.ndarray]:
    """The frames of the scene's video that are measured (:func:`measured_frames`), checked: enough of them, of the
    camera's size."""
    frames = [frame.image for frame in FrameSource(scene.video_path, measured_frames(scene.video_path))]
    if len(frames) < MIN_VIDEO_FRAMES:
        raise InputError(scene.path, "video", f"{scene.video_path.name} holds {len(frames)} readable frame(s); "
                                              f"measuring the camera's noise needs at least {MIN_VIDEO_FRAMES}")
    sizes = {frame.shape[1::-1] for frame in frames}
    if sizes != {tuple(scene.camera.size)}:
        raise InputError(scene.path, "video", f"frames are {sorted(sizes)}, the camera is "
                                              f"{scene.camera.width}x{scene.camera.height}")
    return frames


def measure_camera(scene: Scene) -> CameraMeasurements:
    """Measure the scene's camera from its background and, when it gives one, its video."""
    background = read_image(scene.image_path)
    response = scene.camera_response().response
    background_noise = estimate_noise_image(background, response)
    background_compression = estimate_jpeg(background)
    blur = estimate_blur_sigma(background)
    if scene.video_path is None:
        return CameraMeasurements("the background (the only frame the scene gives)", background_noise,
                                  background_noise, background_compression, background_compression, blur)
    frames = video_frames(scene)
    noise = estimate_noise_video(frames, background, response)
    return CameraMeasurements(f"{len(frames)} frames of {scene.video_path.name}", noise, background_noise,
                              video_compression(frames, background, noise.model, response), background_compression,
                              blur)


def video_compression(frames: list[np.ndarray], background: np.ndarray, noise: NoiseModel, response: Response
                      ) -> JpegEstimate:
    """The frames' compression: the JPEG quality most of them are a fixed point of (a motion-JPEG camera), else
    the JPEG quality that blocks the background, with the frames' ``noise`` added as the sensor adds it, as
    visibly as the frames are blocked (a video codec: 4:2:0, as they code chroma; noise dilutes blocking, so it is
    matched with the noise in), else none."""
    sampled = frames[:: max(1, len(frames) // 6)]
    ghosts = [estimate_jpeg(frame) for frame in sampled]
    found = [estimate.quality for estimate in ghosts if estimate.quality is not None]
    frame_blocking = float(np.median([blockiness(frame) for frame in sampled]))
    evidence = {"frames": len(sampled), "ghost_qualities": found, "frame_blockiness": round(frame_blocking, 4),
                "background_blockiness": round(blockiness(background), 4)}
    if len(found) * 2 > len(ghosts):
        subsampled = sum(estimate.chroma_subsampling for estimate in ghosts) * 2 > len(ghosts)
        return JpegEstimate(int(np.median(found)), subsampled, evidence | {"method": "JPEG ghost"})
    noisy = response.encode(noise.apply(response.decode(background), np.random.default_rng(0)))
    evidence["noisy_background_blockiness"] = round(blockiness(noisy), 4)
    if frame_blocking - evidence["noisy_background_blockiness"] < MIN_BLOCKINESS_EXCESS:
        return JpegEstimate(None, False, evidence | {"method": "blockiness: no visible blocking"})
    quality = equivalent_quality(noisy, frame_blocking)
    return JpegEstimate(quality, quality is not None, evidence | {"method": "blockiness matched on the background"})
