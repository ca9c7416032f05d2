"""What the scene's own images say about its camera: noise, compression and blur, measured once per render.

The detector will see the camera's *frames*. When the scene gives a video (``video:``), the frames are measured
directly: noise from the temporal variance of static pixels, compression from a few frames. Without one, the
background is the only frame there is, and is measured itself. The background is measured too, because what
it already carries must not be added twice: a temporal-median background (PETS09's) is nearly free of noise and
compression, a single frame is not, a rendered one (the demo's) has neither.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from vc.calibration.compression import JpegEstimate, estimate_jpeg
from vc.calibration.noise import NoiseEstimate, estimate_noise_image, estimate_noise_video
from vc.calibration.response import Response
from vc.calibration.sharpness import BlurEstimate, estimate_blur_sigma
from vc.frames import FrameRange, FrameSource
from vc.io import read_image
from vc.scenes.loader import Scene

#: Frames of the scene's video that are measured, spread evenly over its first :data:`VIDEO_SPAN` frames.
VIDEO_FRAMES = 24
VIDEO_SPAN = 240


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
    return {"quality": estimate.quality, "chroma_subsampling": estimate.chroma_subsampling}


def _video_frames(scene: Scene) -> list[np.ndarray]:
    step = max(1, VIDEO_SPAN // VIDEO_FRAMES)
    source = FrameSource(scene.video_path, FrameRange(1, VIDEO_SPAN, step))
    frames = [frame.image for frame in source]
    sizes = {frame.shape[1::-1] for frame in frames}
    if sizes != {tuple(scene.camera.size)}:
        from vc.errors import InputError

        raise InputError(scene.path, "video", f"frames are {sorted(sizes)}, the camera is "
                                              f"{scene.camera.width}x{scene.camera.height}")
    return frames


def measure_camera(scene: Scene) -> CameraMeasurements:
    """Measure the scene's camera from its background and, when it gives one, its video."""
    background = read_image(scene.image_path)
    response = Response(scene.response)
    background_noise = estimate_noise_image(background, response)
    background_compression = estimate_jpeg(background)
    blur = estimate_blur_sigma(background)
    if scene.video_path is None:
        return CameraMeasurements("the background (the only frame the scene gives)", background_noise,
                                  background_noise, background_compression, background_compression, blur)
    frames = _video_frames(scene)
    noise = estimate_noise_video(frames, background, response)
    qualities = [estimate_jpeg(frame) for frame in frames[:: max(1, len(frames) // 6)]]
    found = [estimate.quality for estimate in qualities if estimate.quality is not None]
    if len(found) * 2 > len(qualities):
        quality = int(np.median(found))
        subsampled = sum(estimate.chroma_subsampling for estimate in qualities) * 2 > len(qualities)
        compression = JpegEstimate(quality, subsampled, {"frames": len(qualities), "qualities": found})
    else:
        compression = JpegEstimate(None, False, {"frames": len(qualities), "qualities": found})
    return CameraMeasurements(f"{len(frames)} frames of {scene.video_path.name}", noise, background_noise,
                              compression, background_compression, blur)
