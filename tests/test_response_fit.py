"""``response: auto``: the colour-edge fit recovers known curves, and says so when an image does not show one."""

from __future__ import annotations

import cv2
import numpy as np
import pytest
from scene_factory import modified, write_scene

from vc.calibration.compression import jpeg_round_trip
from vc.calibration.response import Response
from vc.calibration.response_fit import FALLBACK, fit_response
from vc.io import read_image
from vc.scenes.loader import load_scene


def _patchwork(seed: int, height: int = 300, width: int = 400) -> np.ndarray:
    """Linear light: overlapping rectangles of random colours, their edges blurred as a lens blurs them."""
    rng = np.random.default_rng(seed)
    image = np.zeros((height, width, 3), np.float32)
    for _ in range(50):
        x, y = rng.integers(0, width), rng.integers(0, height)
        w, h = rng.integers(20, 140, 2)
        image[y : y + h, x : x + w] = rng.uniform(0.02, 0.9, 3)
    return cv2.GaussianBlur(image, (0, 0), 1.0)


@pytest.mark.parametrize("name", ["linear", "gamma 1.8", "gamma 2.2", "srgb", "gamma 2.6"])
def test_the_curve_an_image_was_encoded_with_is_recovered(name: str) -> None:
    linear = _patchwork(1) + np.random.default_rng(2).normal(0.0, 0.002, (300, 400, 3))
    fit = fit_response(Response(name).encode_exact(np.clip(linear, 0.0, 1.0)))
    assert fit.identified and fit.name == name, fit.reason
    assert fit.misfits[name] == min(fit.misfits.values()) and fit.edges >= 200


def test_chroma_subsampled_images_fall_back_to_srgb_and_say_why() -> None:
    """4:2:0 chroma blurs colour twice as wide as luma: edge pixels stop being mixtures, and no curve fits."""
    encoded = Response("gamma 1.8").encode_exact(_patchwork(3))
    fit = fit_response(jpeg_round_trip(encoded, 90, chroma_subsampling=True))
    assert not fit.identified and fit.name == FALLBACK and "assumed" in fit.reason


def test_an_image_without_colour_edges_is_not_fitted() -> None:
    grey = np.repeat(Response("gamma 2.6").encode_exact(_patchwork(4).mean(axis=2, keepdims=True)), 3, axis=2)
    fit = fit_response(grey)
    assert not fit.identified and fit.name == FALLBACK and fit.edges < 200


def test_a_scene_names_its_response_or_gets_the_fit(tmp_path) -> None:
    """``auto`` on a grey background (no edges): sRGB, with the reason; a named response is taken as named."""
    auto = modified(lambda scene: scene["camera"].update(response="auto"))
    fit = load_scene(write_scene(tmp_path / "auto", auto)).camera_response()
    assert fit.name == FALLBACK and not fit.identified and "0 usable colour edges" in fit.reason
    named = modified(lambda scene: scene["camera"].update(response="gamma 2.2"))
    fit = load_scene(write_scene(tmp_path / "named", named)).camera_response()
    assert fit.name == "gamma 2.2" and fit.identified and fit.reason == "given by the scene"


def test_pets09_background_is_reported_as_not_identifying_its_curve(pets_data) -> None:
    """S2.L1 is Xvid video (4:2:0): its temporal-median background does not show a curve, and the fit says so."""
    fit = fit_response(read_image(pets_data / "background.png"))
    assert not fit.identified and fit.name == "srgb"
