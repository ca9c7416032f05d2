"""A synthetic background photograph of a layout, seen through a real camera.

Used where a scene has no real image yet (the bundled demo) and to check a layout against its camera: the
layout is rendered through an ideal pinhole that covers the camera's view, warped into the real image (lens
distortion included), and encoded to sRGB like a camera's output.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from vc.calibration.camera import Camera
from vc.calibration.lighting import Illumination
from vc.calibration.response import Response
from vc.render.layout_scene import layout_scene_dict
from vc.render.mitsuba_setup import mitsuba
from vc.render.sensor import ideal_view, perspective_sensor
from vc.scenes.layout import Layout

if TYPE_CHECKING:
    import mitsuba as mi

#: Samples per pixel in one call of ``mi.render``: Mitsuba traces a whole pass as one wavefront, so this caps
#: the memory a render needs (the 960 x 540 demo peaks at about 0.6 GB for the whole process).
SPP_PER_PASS = 16


def pass_seed(seed: int, index: int) -> int:
    """The sampler seed of pass ``index`` of a render seeded ``seed``: distinct passes never share samples."""
    return int(np.random.SeedSequence([seed, index]).generate_state(1)[0])


def render_linear(scene: mi.Scene, spp: int, seed: int, spp_per_pass: int = SPP_PER_PASS) -> np.ndarray:
    """Render ``scene`` (a loaded Mitsuba scene) with ``spp`` samples per pixel, in passes: linear (H, W, 3).

    The result depends only on (scene, spp, seed, spp_per_pass): each pass has its own derived seed.
    """
    if spp < 1:
        raise ValueError(f"samples per pixel must be at least 1, got {spp}")
    mi = mitsuba()
    full, rest = divmod(spp, spp_per_pass)
    passes = [spp_per_pass] * full + ([rest] if rest else [])
    total = None
    for index, count in enumerate(passes):
        image = np.asarray(mi.render(scene, seed=pass_seed(seed, index), spp=count), dtype=np.float64) * count
        total = image if total is None else total + image
    return (total / spp)[..., :3].astype(np.float32)


def render_background(camera: Camera, layout: Layout, illumination: Illumination, spp: int = 64, seed: int = 0
                      ) -> np.ndarray:
    """The layout under ``illumination`` as ``camera`` would photograph it: sRGB uint8 (height, width, 3).

    ``seed`` fixes both the procedural ground texture and the sampler, so equal arguments give equal bytes.
    """
    view = ideal_view(camera)
    scene_dict = layout_scene_dict(layout, illumination, perspective_sensor(view.ideal, spp), seed=seed)
    scene = mitsuba().load_dict(scene_dict)
    linear = render_linear(scene, spp, seed)
    return Response("srgb").encode_exact(view.warp(linear))
