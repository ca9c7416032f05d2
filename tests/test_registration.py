"""vc.deploy.registration and the roll's registration: a view moved and turned is undone to the background's, a
person found on it is put back where the camera shows them, the halves read a roll's sign, and on PETS09's real
frames a camera rolled a fraction of a degree is left to the networks while one rolled a degree or more is read as
moved and registered to a pixel and 0.15 degree (docs/decisions/0026-camera-roll.md)."""

from __future__ import annotations

import cv2
import numpy as np
import pytest
from conftest import PETS_DATA

from vc.calibration.response import Response
from vc.deploy import fitness as fit
from vc.deploy.fitness import SceneReference
from vc.deploy.registration import HalvesReference, Registration, translated, view_back

#: The sRGB decoding table the PETS09 reference is made with (as the fitness tests make theirs).
DECODE = Response("srgb").decode(np.arange(256, dtype=np.uint8))


def _texture(size: tuple[int, int] = (320, 240), seed: int = 5) -> np.ndarray:
    """A textured view (structure over a few pixels and over tens, in colour)."""
    width, height = size
    rng = np.random.default_rng(seed)
    fine = cv2.GaussianBlur(rng.normal(0, 1, (height, width, 3)).astype(np.float32), (0, 0), 2.0)
    coarse = cv2.GaussianBlur(rng.normal(0, 1, (height, width, 3)).astype(np.float32), (0, 0), 12.0)
    image = 128 + 40 * fine / fine.std() + 40 * coarse / coarse.std()
    return np.clip(image, 0, 255).astype(np.uint8)


def turned(frame: np.ndarray, registration: Registration) -> np.ndarray:
    """What a camera whose view moved by ``registration`` shows: the content at ``p`` moves to ``matrix @ p``
    (bilinear, OpenCV)."""
    height, width = frame.shape[:2]
    return cv2.warpAffine(frame, registration.matrix((width, height)), (width, height), flags=cv2.INTER_LINEAR,
                          borderMode=cv2.BORDER_REPLICATE)


@pytest.mark.parametrize("registration", [Registration(4, -3), Registration(0, 0, 2.0),
                                          Registration(-6, 5, -1.5)])
def test_a_view_undone_shows_the_background(registration):
    background = _texture()
    undone = view_back(turned(background, registration), registration)
    inner = (slice(20, -20), slice(20, -20))  # the corners the frame no longer shows are the edge's pixels
    error = np.abs(undone[inner].astype(int) - background[inner]).mean()  # the nearest pixel against bilinear
    assert error < 0.25 * np.abs(turned(background, registration)[inner].astype(int) - background[inner]).mean()
    assert view_back(background, Registration()) is background


def test_a_point_found_on_the_view_undone_is_put_where_the_camera_shows_it():
    frame = np.zeros((101, 201, 3), np.uint8)
    frame[45:56, 175:186] = 255  # a bright square at (180, 50): 80 px right of the centre (100, 50)
    registration = Registration(3, -2, 2.0)
    weights = turned(frame, registration)[..., 0].astype(float)
    rows, columns = np.indices(weights.shape)
    seen = ((columns * weights).sum() / weights.sum(), (rows * weights).sum() / weights.sum())
    # counter-clockwise on the screen: the point right of the centre goes up, then the move
    assert seen == pytest.approx((100 + 80 * np.cos(np.radians(2)) + 3, 50 - 80 * np.sin(np.radians(2)) - 2), abs=0.1)
    assert registration.forward(np.array([[180.0, 50.0]]), (201, 101))[0] == pytest.approx(seen, abs=0.1)
    assert Registration(5, 7).forward(np.array([[1.0, 2.0]]), (201, 101)).tolist() == [[6.0, 9.0]]


def test_translated_is_a_whole_pixel_move():
    frame = _texture((60, 40))
    assert np.array_equal(translated(frame, (3, -2))[5:-5, 5:-5], frame[3:-7, 8:-2])


def test_the_halves_read_a_roll_with_its_sign_and_short():
    luma = _texture((96, 72))[..., 1].astype(np.float32)
    halves = HalvesReference(luma)
    assert halves.roll(luma, 0.15) == pytest.approx(0.0, abs=1e-6)
    for degrees in (1.5, -1.5):
        read = halves.roll(turned(luma, Registration(roll_deg=degrees)), 0.15)
        assert np.sign(read) == np.sign(degrees) and 0.2 * abs(degrees) < abs(read) < 1.2 * abs(degrees)


def test_a_half_without_a_clear_peak_does_not_read_a_roll():
    luma = _texture((96, 72))[..., 1].astype(np.float32)
    halves = HalvesReference(luma)
    crowded = turned(luma, Registration(roll_deg=1.5))
    crowded[:, 56:] = np.random.default_rng(1).normal(128, 40, (72, 40))  # a crowd or noise hides its right part
    assert abs(halves.roll(crowded, 0.0)) > 3.0  # every half counted, the hidden ones move anywhere
    assert halves.roll(crowded, 0.15) == 0.0  # neither pair clear: no roll read
    assert halves.roll(np.random.default_rng(2).normal(128, 40, (72, 96)), 0.15) == 0.0


@pytest.fixture(scope="module")
def pets(pets_data) -> tuple[SceneReference, list[np.ndarray]]:
    from vc.io import read_image

    capture, frames = cv2.VideoCapture(str(PETS_DATA / "vtest.avi")), []
    for number in range(1, 302):
        ok, bgr = capture.read()
        assert ok
        if number in (1, 151, 301):
            frames.append(cv2.cvtColor(bgr, cv2.COLOR_BGR2RGB))
    return SceneReference.of_background(read_image(pets_data / "background.png"), DECODE), frames


def test_pets09_a_fraction_of_a_degree_is_left_to_the_networks(pets):
    reference, frames = pets
    for frame in frames:
        assert reference.fitness(frame).state == fit.OK
        fitness = reference.fitness(turned(frame, Registration(roll_deg=0.5)))
        assert fitness.state == fit.OK and 0.05 < fitness.roll_deg < fit.ROLLED_DEG


@pytest.mark.parametrize("registration", [Registration(0, 0, 1.0), Registration(0, 0, -2.0),
                                          Registration(7, -4, 1.5)])
def test_pets09_a_rolled_view_reads_moved_and_is_registered_within_0_15_degree(pets, registration):
    reference, frames = pets
    for frame in frames:
        rolled = turned(frame, registration)
        fitness = reference.fitness(rolled)
        assert fitness.state == fit.MOVED
        found = reference.register(rolled)
        # the move to a pixel (the view undone takes the nearest), the roll within 0.15 degree
        assert np.abs(np.subtract(found.shift, registration.shift)).max() <= 1
        assert found.roll_deg == pytest.approx(registration.roll_deg, abs=0.15)
        assert reference.fitness(view_back(rolled, found)).state == fit.OK


def test_pets09_a_roll_beyond_the_bound_is_not_registered(pets):
    reference, frames = pets
    assert reference.register(turned(frames[0], Registration(roll_deg=fit.REGISTRATION_BOUND_DEG + 2))) is None
