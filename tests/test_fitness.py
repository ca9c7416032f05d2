"""Scene fitness (vc.deploy.fitness) on the hard cases a camera meets: black, uniform, noise, dark, bright, white
balance, IR monochrome, blur and a nudge, on a compiled test bundle given a background reference and on the real
PETS09 and TUD-Stadtmitte frames; a covered frame never yields people; the numbers stay finite on extreme frames; a
bundle without a reference reports ``unknown``, a damaged one is refused by name."""

from __future__ import annotations

import json
import math
import shutil
from pathlib import Path

import numpy as np
import pytest
from conftest import PETS_DATA, REPO
from dataset_factory import INPUT_SIZE
from hard_cases.hard_case_settings import PROPERTY
from hypothesis import given
from hypothesis import strategies as st

from vc.calibration.response import Response
from vc.cli.run import main as vc_run
from vc.deploy import exposure, veil
from vc.deploy import fitness as fit
from vc.deploy.bundle import MANIFEST, NO_REFERENCE, REFERENCE_MEMBER, load_bundle, sha256
from vc.deploy.fitness import FrameFitness, SceneReference
from vc.deploy.registration import Registration, translated
from vc.deploy.runtime import Runtime
from vc.errors import InputError
from vc.io import write_image
from vc.model.export import with_reference, write_bundle

SRGB = Response("srgb")
DECODE = SRGB.decode(np.arange(256, dtype=np.uint8))
TUD_FRAMES = REPO.parent / "shared" / "data" / "tud_stadtmitte" / "frames"
NUMBERS = ("spread", "coherence", "exposure_stops", "matching", "sharpness", "shift_peak", "colour_left",
           "colour_cast_stops", "veil", "noise_codes", "correlation")


def _smooth(rng: np.random.Generator, shape: tuple[int, int], size: int) -> np.ndarray:
    """Noise smoothed over about ``size`` pixels (numpy only: a Gaussian in the Fourier domain), zero mean, unit
    spread."""
    spectrum = np.fft.rfft2(rng.normal(size=shape))
    fy, fx = np.fft.fftfreq(shape[0])[:, None], np.fft.rfftfreq(shape[1])[None, :]
    field = np.fft.irfft2(spectrum * np.exp(-2 * (np.pi * size) ** 2 * (fx ** 2 + fy ** 2)), s=shape)
    return (field - field.mean()) / field.std()


def scene_background(size: tuple[int, int] = INPUT_SIZE, seed: int = 7) -> np.ndarray:
    """A stand-in for a scene's background at ``size``: coloured ground (greyish paving, greener and redder
    patches) varying over a few pixels and over tens, sharp-edged blocks (kerbs, a building) and a little sensor
    noise — the structure and colour the fitness measurements read, not a ramp."""
    width, height = size
    rng = np.random.default_rng(seed)
    image = np.empty((height, width, 3), np.float32)
    broad, fine = _smooth(rng, (height, width), 8), _smooth(rng, (height, width), 1.5)
    image[:] = 120 + 30 * broad[..., None] + 10 * fine[..., None]
    image[..., 1] += 25 * _smooth(rng, (height, width), 10)  # grass-like patches
    image[..., 0] += 20 * _smooth(rng, (height, width), 12)
    for _ in range(6):  # sharp-edged blocks of their own colour
        x0, y0 = rng.integers(0, width - 20), rng.integers(0, height - 12)
        image[y0:y0 + rng.integers(6, 16), x0:x0 + rng.integers(8, 30)] = rng.uniform(40, 220, 3)
    image += rng.normal(0, 1.0, image.shape)
    return np.clip(image, 0, 255).round().astype(np.uint8)


def exposed(image: np.ndarray, stops: float) -> np.ndarray:
    return SRGB.encode(SRGB.decode(image) * np.float32(2.0 ** stops))


def gains(image: np.ndarray, red: float, blue: float) -> np.ndarray:
    return np.clip(image * np.array([red, 1.0, blue], np.float32), 0, 255).astype(np.uint8)


def linear_gains(image: np.ndarray, red: float, blue: float) -> np.ndarray:
    """White balance as a camera gets it wrong: gains on the light, not on the codes."""
    return SRGB.encode(SRGB.decode(image) * np.array([red, 1.0, blue], np.float32))


def low_contrast(image: np.ndarray, kept: float, mean: np.ndarray | None = None) -> np.ndarray:
    """``kept`` of the image's contrast, its codes drawn toward ``mean`` (default: their own; COCO-C's contrast, a
    camera's own)."""
    mean = image.reshape(-1, 3).mean(axis=0) if mean is None else mean
    return np.clip((image - mean) * kept + mean, 0, 255).round().astype(np.uint8)


def fogged_light(image: np.ndarray, transmission: float) -> np.ndarray:
    """A veil of airlight over the light (Koschmieder: ``t L + (1 - t) A``, A the light's median), through sRGB."""
    light = SRGB.decode(image)
    return SRGB.encode(np.float32(transmission) * light + np.float32(1 - transmission) * np.median(light))


def monochrome(image: np.ndarray) -> np.ndarray:
    luma = (image @ np.array([0.299, 0.587, 0.114], np.float32)).round().astype(np.uint8)
    return np.repeat(luma[..., None], 3, axis=2)


def blurred(image: np.ndarray, sigma: float) -> np.ndarray:
    """A Gaussian blur (numpy only, in the Fourier domain, the border wrapped)."""
    fy, fx = np.fft.fftfreq(image.shape[0])[:, None], np.fft.rfftfreq(image.shape[1])[None, :]
    kernel = np.exp(-2 * (np.pi * sigma) ** 2 * (fx ** 2 + fy ** 2))
    out = np.stack([np.fft.irfft2(np.fft.rfft2(image[..., c].astype(np.float64)) * kernel, s=image.shape[:2])
                    for c in range(3)], axis=-1)
    return np.clip(out, 0, 255).round().astype(np.uint8)


def shifted(image: np.ndarray, dx: int, dy: int) -> np.ndarray:
    """The view moved by (dx, dy) pixels: the content moves, the edge it leaves repeats its border."""
    padded = np.pad(image, ((abs(dy), abs(dy)), (abs(dx), abs(dx)), (0, 0)), mode="edge")
    height, width = image.shape[:2]
    return np.ascontiguousarray(padded[abs(dy) - dy:abs(dy) - dy + height, abs(dx) - dx:abs(dx) - dx + width])


#: The hard cases on the test scene: name -> (frame from the background, the state it must read).
HARD_CASES = {
    "black": (np.zeros_like, fit.COVERED),
    "white": (lambda image: np.full_like(image, 255), fit.COVERED),
    "uniform grey": (lambda image: np.full_like(image, 128), fit.COVERED),
    "noise": (lambda image: np.random.default_rng(0).integers(0, 256, image.shape, dtype=np.uint8), fit.COVERED),
    # -2 and +2 stops are within a stop of its bounds (1.25): the runtime brings them back (test_light_within_...)
    "-3 stops": (lambda image: exposed(image, -3), fit.DARK),
    "-4 stops": (lambda image: exposed(image, -4), fit.DARK),
    "+3 stops": (lambda image: exposed(image, 3), fit.OVEREXPOSED),
    "white balance warm": (lambda image: gains(image, 1.25, 0.8), fit.CHANGED),
    "white balance cool": (lambda image: gains(image, 0.8, 1.25), fit.CHANGED),
    "IR monochrome": (monochrome, fit.CHANGED),
}


def _numbers_finite(fitness: FrameFitness) -> bool:
    values = [getattr(fitness, name) for name in NUMBERS] + list(fitness.shift_px)
    return all(value is None or math.isfinite(value) for value in values)


def _networks_people(runtime: Runtime, frame: np.ndarray) -> list:
    """What the bundle's networks find in ``frame``, whatever its fitness."""
    return [person for runner in runtime.runners for person in runner.people(frame)]


def _bundle_files(folder: Path) -> tuple[dict, dict[str, bytes]]:
    manifest = json.loads((folder / MANIFEST).read_text())
    files = {path.relative_to(folder).as_posix(): path.read_bytes() for path in folder.rglob("*")
             if path.is_file() and path.name != MANIFEST}
    return manifest, files


@pytest.fixture(scope="module")
def background() -> np.ndarray:
    return scene_background()


@pytest.fixture(scope="module")
def referenced_bundle(bundle, background, tmp_path_factory) -> Path:
    """The compiled test bundle carrying the test scene's background as its reference, decoding every centre peak
    above 0.001 as a person, so that its network reports people on any frame: what withholding them changes shows."""
    manifest, files = _bundle_files(bundle)
    for region in manifest["regions"]:
        region["decode"]["centre_threshold"] = 0.001
    manifest, files = with_reference(manifest, files, SceneReference.of_background(background, DECODE),
                                     "the test scene's background")
    output = tmp_path_factory.mktemp("referenced") / "bundle"
    write_bundle(manifest, files, output, as_zip=False)
    return output


def test_the_reference_round_trips_and_the_background_itself_is_ok(referenced_bundle, background):
    loaded = load_bundle(referenced_bundle)
    made = SceneReference.of_background(background, DECODE)
    assert np.array_equal(loaded.reference.cells, made.cells) and loaded.reference.cell_px == fit.MIN_CELL_PX
    fitness = loaded.reference.fitness(background)
    assert fitness.state == fit.OK and fitness.reason == ""
    assert fitness.exposure_stops == 0 and fitness.matching == 1 and fitness.shift_px == pytest.approx((0, 0), abs=1e-6)
    assert fitness.sharpness == pytest.approx(1) and fitness.colour_left == pytest.approx(1)
    assert fitness.colour_cast_stops == 0 and fitness.spread == pytest.approx(1)


@pytest.mark.parametrize("case", list(HARD_CASES))
def test_each_hard_case_reads_its_state_and_an_unfit_frame_yields_no_people(referenced_bundle, background, case):
    change, expected = HARD_CASES[case]
    frame = change(background)
    with Runtime(referenced_bundle, threads=1) as runtime:
        result = runtime.run(frame)
        assert result.fitness.state == expected, result.fitness
        assert result.fitness.reason and _numbers_finite(result.fitness)
        assert result.suppressed and result.people == [] and runtime(frame) == []
        assert runtime.last_fitness.state == expected
        assert _networks_people(runtime, frame), "the test bundle's network reports people on any frame"
    with Runtime(referenced_bundle, threads=1, unfit="flag") as runtime:
        people = runtime(frame)
        if expected == fit.COVERED:  # whatever the setting
            assert people == []
        else:
            assert people and all(person.unfit == expected and person.to_dict()["unfit"] == expected
                                  for person in people)


def test_a_fit_frame_keeps_its_people_unflagged(referenced_bundle, background):
    frame = background.copy()
    frame[24:40, 60:66] = (40, 50, 60)  # someone standing there, a quarter of the frame tall (PETS09: 50-100 of 576 px)
    with Runtime(referenced_bundle, threads=1) as runtime:
        result = runtime.run(frame)
        assert result.fitness.state == fit.OK and not result.suppressed
        assert result.people and all(person.unfit is None and "unfit" not in person.to_dict()
                                     for person in result.people)
        assert result.reported(result.people) == result.people


@pytest.mark.parametrize("stops", [-2.0, 2.0])
def test_light_within_reach_beyond_the_range_is_brought_back_and_its_people_kept(referenced_bundle, background,
                                                                                 stops):
    with Runtime(referenced_bundle, threads=1) as runtime:
        assert runtime.fitness(exposed(background, stops)).state in (fit.DARK, fit.OVEREXPOSED)
        result = runtime.run(exposed(background, stops))
        corrected = result.fitness.exposure_corrected_stops
        assert result.fitness.state == fit.OK and not result.suppressed
        assert corrected == pytest.approx(-stops, abs=0.1)
        assert result.fitness.to_dict()["exposure_corrected_stops"] == pytest.approx(corrected, abs=1e-3)
        assert result.fitness.exposure_stops == pytest.approx(0, abs=0.1)  # judged again, brought back
        assert result.people and all(person.unfit is None for person in result.people)
        # the networks ran on the frame brought back
        brought_back = runtime.run(exposure.exposed(exposed(background, stops), DECODE, corrected))
    assert sorted(person.box.tolist() for person in result.people) \
        == sorted(person.box.tolist() for person in brought_back.people)


def test_the_correction_is_kept_while_the_frames_need_it(referenced_bundle, background):
    with Runtime(referenced_bundle, threads=1) as runtime:
        first = runtime.run(exposed(background, 1.8)).fitness.exposure_corrected_stops
        assert first == pytest.approx(-1.8, abs=0.1) and runtime.exposure_correction == first
        following = runtime.run(exposed(background, 1.9))  # the camera's light drifts: the correction is kept
        assert following.fitness.state == fit.OK and following.fitness.exposure_corrected_stops == first
        assert following.fitness.exposure_stops == pytest.approx(0.1, abs=0.1)
        back = runtime.run(background)  # within the range again: given to the networks as it is
        assert back.fitness.state == fit.OK and back.fitness.exposure_corrected_stops is None
        assert runtime.exposure_correction is None and back.fitness.exposure_stops == 0
        assert runtime.run(exposed(background, -2.0)).fitness.exposure_corrected_stops == pytest.approx(2, abs=0.1)
        assert runtime.run(exposed(background, 4.0)).fitness.state == fit.OVEREXPOSED  # beyond the reach
        assert runtime.exposure_correction is None


def test_light_beyond_the_range_over_a_view_changed_otherwise_stays_withheld(referenced_bundle, background):
    frame = exposed(background, 1.75)
    height, width = frame.shape[:2]
    frame[:, : width * 2 // 5] = np.random.default_rng(5).integers(200, 256, (height, width * 2 // 5, 3))  # snow
    with Runtime(referenced_bundle, threads=1) as runtime:
        result = runtime.run(frame)
    assert result.fitness.state == fit.OVEREXPOSED and result.suppressed
    assert result.fitness.exposure_corrected_stops is None and "exposure_corrected_stops" not in \
        result.fitness.to_dict()


#: Views under a veil beyond the test bundle's range (module docstring of vc.deploy.veil): name -> (frame maker, the
#: median code the frame stretched back may miss the background by: stretched 20x, a rounded code is a step of 20).
VEILS = {
    "a tenth of the contrast (dark)": (lambda image: low_contrast(image, 0.1), 3),
    "a twentieth of the contrast (covered)": (lambda image: low_contrast(image, 0.05), 6),
    "fog letting 8 % of the light through": (lambda image: fogged_light(image, 0.08), 3),
}


@pytest.mark.parametrize("name", list(VEILS))
def test_a_view_under_a_veil_beyond_the_range_is_stretched_back_and_its_people_kept(referenced_bundle, background,
                                                                                   name):
    make, missed_codes = VEILS[name]
    frame = make(background)
    with Runtime(referenced_bundle, threads=1) as runtime:
        assert runtime.fitness(frame).state in (fit.DARK, fit.COVERED)
        result = runtime.run(frame)
        assert result.fitness.state == fit.OK and not result.suppressed and result.people
        assert result.fitness.veil_taken_off > 0.5 and result.fitness.to_dict()["veil_taken_off"] > 0.5
        assert result.fitness.exposure_corrected_stops is None and result.fitness.matching > 0.8
        stretched = veil.unveiled(frame, runtime.veil_correction)
        # what the networks saw is the background's tone again, to within the codes the veil took
        assert np.median(np.abs(stretched.astype(int) - background)) <= missed_codes
        assert sorted(person.box.tolist() for person in result.people) \
            == sorted(person.box.tolist() for person in runtime.run(stretched).people)


@pytest.mark.parametrize(("name", "frame_of"), [
    ("a fortieth of the contrast: too few codes left", lambda image: low_contrast(image, 1 / 40)),
    ("light through a covering hand: no view", lambda image: np.clip(
        128 + 2 * _smooth(np.random.default_rng(3), image.shape[:2], 20)[..., None], 0, 255).astype(np.uint8)
     .repeat(3, axis=2)),
    ("another view, faint", lambda image: low_contrast(image[::-1, ::-1], 0.05)),
])
def test_a_covered_frame_stays_covered_and_yields_no_one(referenced_bundle, background, name, frame_of):
    frame = np.ascontiguousarray(frame_of(background))
    with Runtime(referenced_bundle, threads=1) as runtime:
        result = runtime.run(frame)
        assert result.fitness.state == fit.COVERED and result.suppressed and result.people == []
        assert result.fitness.veil_taken_off is None and runtime.veil_correction is None


def test_the_veil_s_tables_are_kept_while_the_frames_need_about_as_much(referenced_bundle, background):
    with Runtime(referenced_bundle, threads=1) as runtime:
        runtime.run(low_contrast(background, 0.1))
        tables = runtime.veil_correction
        assert tables is not None and tables.shape == (3, 256)
        following = background.copy()
        following[24:40, 60:66] = (40, 50, 60)  # someone walked into the same veil
        result = runtime.run(low_contrast(following, 0.1, background.reshape(-1, 3).mean(axis=0)))
        assert result.fitness.veil_taken_off is not None and runtime.veil_correction is tables
        assert runtime.run(following).fitness.veil_taken_off is None  # the fog lifted
        assert runtime.veil_correction is None


@pytest.mark.parametrize(("name", "frame"), [
    ("all 0", np.zeros((64, 128, 3), np.uint8)),
    ("all 255", np.full((64, 128, 3), 255, np.uint8)),
    ("one bright pixel", np.pad(np.full((1, 1, 3), 255, np.uint8), ((30, 33), (60, 67), (0, 0)))),
    ("one bright column", np.pad(np.full((64, 1, 3), 255, np.uint8), ((0, 0), (5, 122), (0, 0)))),
    ("one bright row", np.pad(np.full((1, 128, 3), 200, np.uint8), ((63, 0), (0, 0), (0, 0)))),
    ("alternating columns", np.tile(np.array([0, 255], np.uint8)[None, :, None], (64, 64, 3))),
    ("one channel only", np.pad(np.full((64, 128, 1), 255, np.uint8), ((0, 0), (0, 0), (0, 2)))),
])
def test_the_numbers_stay_finite_on_extreme_frames_and_references(background, name, frame):
    for reference_image in (background, frame, np.zeros_like(frame), np.full_like(frame, 255)):
        reference = SceneReference.of_background(reference_image, DECODE)
        for measured in (frame, background, np.zeros_like(frame)):
            fitness = reference.fitness(measured)
            assert fitness.state in fit.STATES and _numbers_finite(fitness), (name, fitness)
            json.dumps(fitness.to_dict(), allow_nan=False)


@st.composite
def _drawn_frames(draw) -> np.ndarray:
    """A 128x64 frame of a flat colour, rectangles of other colours (down to one pixel, up to the frame), and noise
    of any strength: every extreme the measurements meet in a frame or a background."""
    frame = np.empty((64, 128, 3), np.uint8)
    frame[:] = draw(st.tuples(*[st.integers(0, 255)] * 3))
    for _ in range(draw(st.integers(0, 6))):
        x0, y0 = draw(st.integers(0, 127)), draw(st.integers(0, 63))
        frame[y0:y0 + draw(st.integers(1, 64)), x0:x0 + draw(st.integers(1, 128))] = \
            draw(st.tuples(*[st.integers(0, 255)] * 3))
    sigma = draw(st.sampled_from([0.0, 0.5, 4.0, 40.0, 200.0]))
    if sigma:
        noise = np.random.default_rng(draw(st.integers(0, 2 ** 16))).normal(0, sigma, frame.shape)
        frame = np.clip(frame + noise, 0, 255).astype(np.uint8)
    return frame


@PROPERTY
@given(frame=_drawn_frames(), background=_drawn_frames())
def test_any_frame_against_any_background_gives_a_state_and_finite_numbers(frame, background):
    reference = SceneReference.of_background(background, DECODE)
    fitness = reference.fitness(frame)
    assert fitness.state in fit.STATES and fitness.state != fit.UNKNOWN and _numbers_finite(fitness)
    json.dumps(fitness.to_dict(), allow_nan=False)
    if np.ptp(frame.reshape(-1, 3) @ fit.LUMA) == 0:  # a uniform frame shows no scene
        assert fitness.state == fit.COVERED


def test_a_black_reference_finds_a_black_frame_covered():
    reference = SceneReference.of_background(np.zeros((64, 128, 3), np.uint8), DECODE)
    assert reference.fitness(np.zeros((64, 128, 3), np.uint8)).state == fit.COVERED


def test_blur_and_a_nudge_read_blurred_and_moved_on_the_test_scene(background):
    reference = SceneReference.of_background(background, DECODE)
    assert reference.fitness(blurred(background, 2)).state == fit.BLURRED
    moved = reference.fitness(shifted(background, 12, 0))
    assert moved.state == fit.MOVED and moved.shift_px[0] == pytest.approx(12, abs=2)
    assert reference.fitness(shifted(background, 1, 0)).state == fit.OK


def test_a_bundle_without_a_reference_reports_unknown_and_its_people_as_before(bundle, background):
    with Runtime(bundle, threads=1) as runtime:
        assert runtime.bundle.reference is None
        result = runtime.run(np.zeros_like(background))
        assert result.fitness.state == fit.UNKNOWN and result.fitness.reason == NO_REFERENCE
        assert not result.suppressed and result.fitness.to_dict() == {"state": "unknown"}
        assert sorted(p.box.tolist() for p in runtime(background)) == \
            sorted(p.box.tolist() for p in _networks_people(runtime, background))
        assert runtime.fitness_summary([FrameFitness.unknown(NO_REFERENCE)] * 3)["unknown_because"] == NO_REFERENCE


def test_the_unfit_setting_is_checked(bundle):
    with pytest.raises(InputError, match="unfit: 'drop' is not one of suppress, flag"):
        Runtime(bundle, unfit="drop")


def _damage_bytes(folder: Path) -> None:
    path = folder / REFERENCE_MEMBER
    data = bytearray(path.read_bytes())
    data[len(data) // 2] ^= 0xFF
    path.write_bytes(bytes(data))


def _rewritten(folder: Path, arrays: dict) -> None:
    """The reference replaced by ``arrays`` and the manifest's hash rewritten to match: damaged content that the
    hash does not catch."""
    import io

    buffer = io.BytesIO()
    np.savez(buffer, **arrays)
    _replaced(folder, buffer.getvalue())


def _arrays(folder: Path, **changes) -> dict:
    with np.load(folder / REFERENCE_MEMBER) as archive:
        arrays = {name: archive[name] for name in archive.files}
    arrays.update(changes)
    return {name: value for name, value in arrays.items() if value is not None}


@pytest.mark.parametrize(("damage", "field", "message"), ids=[
    "changed bytes", "missing", "NaN cells", "another frame size", "an array missing", "not an archive"], argvalues=[
    (_damage_bytes, "reference.background_sha256", "reference/background.npz does not match its SHA-256"),
    (lambda folder: (folder / REFERENCE_MEMBER).unlink(), "reference.background",
     "reference/background.npz is missing"),
    (lambda folder: _rewritten(folder, _arrays(folder, cells=np.full((16, 32, 3), np.nan, np.float32))),
     "reference.background", "cells must hold finite numbers"),
    (lambda folder: _rewritten(folder, _arrays(folder, cells=np.zeros((8, 16, 3), np.float32))),
     "reference.background", "do not fit the bundle's 128x64 frames"),
    (lambda folder: _rewritten(folder, _arrays(folder, decode=None)), "reference.background", "lacks the array"),
    (lambda folder: _replaced(folder, b"not an archive"), "reference.background", "not a readable numpy archive"),
])
def test_a_damaged_reference_is_refused_by_name(referenced_bundle, tmp_path, capsys, damage, field, message):
    copy = Path(shutil.copytree(referenced_bundle, tmp_path / "copy"))
    damage(copy)
    with pytest.raises(InputError, match=message) as refused:
        load_bundle(copy)
    assert refused.value.field == f"manifest.json: {field}"
    frames = tmp_path / "frames"
    write_image(frames / "a.png", np.zeros((INPUT_SIZE[1], INPUT_SIZE[0], 3), np.uint8))
    assert vc_run([str(copy), str(frames), "-o", str(tmp_path / "out"), "--quiet"]) == 2
    assert message.split(" (")[0] in capsys.readouterr().err and not (tmp_path / "out").exists()


def _replaced(folder: Path, data: bytes) -> None:
    """The reference's bytes replaced by ``data``, the manifest's hash rewritten to match."""
    (folder / REFERENCE_MEMBER).write_bytes(data)
    manifest = json.loads((folder / MANIFEST).read_text())
    manifest["reference"]["background_sha256"] = sha256(data)
    (folder / MANIFEST).write_text(json.dumps(manifest))


def test_vc_run_writes_each_frames_fitness_and_counts_the_states(referenced_bundle, background, tmp_path, capsys):
    frames = tmp_path / "frames"
    for name, image in (("a-ok", background), ("b-black", np.zeros_like(background)),
                        ("c-dark", exposed(background, -3)), ("d-ok", background),
                        ("e-bright", exposed(background, 1.8)), ("f-veiled", low_contrast(background, 0.1))):
        write_image(frames / f"{name}.png", image)
    output = tmp_path / "out"
    assert vc_run([str(referenced_bundle), str(frames), "-o", str(output), "--threads", "1", "--fps", "5",
                   "--quiet"]) == 0
    lines = [json.loads(line) for line in (output / "detections.jsonl").read_text().splitlines()]
    assert [line["fitness"]["state"] for line in lines] == ["ok", "covered", "dark", "ok", "ok", "ok"]
    assert lines[1]["people"] == [] and lines[2]["people"] == []  # not even people a track carries
    assert lines[0]["people"] and "reason" not in lines[0]["fitness"] and "dark" in lines[2]["fitness"]["reason"]
    assert lines[4]["people"] and lines[4]["fitness"]["exposure_corrected_stops"] == pytest.approx(-1.8, abs=0.1)
    assert lines[5]["people"] and lines[5]["fitness"]["veil_taken_off"] > 0.5
    summary = json.loads((output / "summary.json").read_text())["fitness"]
    assert summary == {"states": {"ok": 4, "dark": 1, "covered": 1}, "unfit_frames": 2, "unfit": "suppress",
                       "exposure_corrected_frames": 1, "veil_taken_off_frames": 1, "registered_frames": 0}
    assert "scene fitness: 4 ok, 1 dark, 1 covered (1 brought back from light beyond the range, 1 with a veil beyond " \
           "the range taken off); the people of the 2 unfit frame(s) withheld" in capsys.readouterr().out
    flagged = tmp_path / "flagged"
    assert vc_run([str(referenced_bundle), str(frames), "-o", str(flagged), "--threads", "1", "--no-tracking",
                   "--unfit", "flag", "--quiet"]) == 0
    lines = [json.loads(line) for line in (flagged / "detections.jsonl").read_text().splitlines()]
    assert lines[1]["people"] == [] and lines[2]["people"]
    assert all(person["unfit"] == "dark" for person in lines[2]["people"])


def test_vc_eval_counts_the_scored_frames_per_state(referenced_bundle, background, tmp_path, capsys):
    from vc.cli.eval import main as vc_eval

    frames = tmp_path / "frames"
    for index, image in enumerate((background, np.zeros_like(background), background, exposed(background, -3))):
        write_image(frames / f"{index:02d}.png", image)
    (tmp_path / "gt.txt").write_text("".join(f"{n},1,60,24,6,16,1,-1,-1,-1\n" for n in range(1, 5)))
    assert vc_eval([str(referenced_bundle), "--video", str(frames), "--gt", str(tmp_path / "gt.txt"), "-o",
                    str(tmp_path / "out"), "--no-hog", "--threads", "1", "--frames", "1:4", "--quiet"]) == 0
    fitness = json.loads((tmp_path / "out" / "metrics.json").read_text())["fitness"]
    assert fitness == {"states": {"ok": 2, "dark": 1, "covered": 1}, "unfit_frames": 2, "unfit": "suppress",
                       "exposure_corrected_frames": 0, "veil_taken_off_frames": 0, "registered_frames": 0}
    assert "scene fitness: 2 ok, 1 dark, 1 covered;" in capsys.readouterr().out
    lines = [json.loads(line) for line in (tmp_path / "out" / "detections.jsonl").read_text().splitlines()]
    assert lines[1]["people"] == [] and lines[3]["people"] == []


def test_vc_run_on_a_bundle_without_a_reference_says_why_fitness_is_unknown(bundle, background, tmp_path, capsys):
    frames = tmp_path / "frames"
    write_image(frames / "a.png", background)
    assert vc_run([str(bundle), str(frames), "-o", str(tmp_path / "out"), "--quiet"]) == 0
    line = json.loads((tmp_path / "out" / "detections.jsonl").read_text())
    assert line["fitness"] == {"state": "unknown"}
    summary = json.loads((tmp_path / "out" / "summary.json").read_text())["fitness"]
    assert summary["states"] == {"unknown": 1} and summary["unknown_because"] == NO_REFERENCE
    assert "scene fitness unknown: the bundle carries no background reference" in capsys.readouterr().out


def test_vc_export_refuses_the_background_of_another_scene(trained_run, tmp_path, capsys):
    from vc.cli.export import main as vc_export

    scene = REPO / "examples" / "scenes" / "demo" / "scene.yaml"
    assert vc_export([str(trained_run), "-o", str(tmp_path / "bundle"), "--scene", str(scene), "--quiet"]) == 2
    error = capsys.readouterr().err
    assert "scene_hash" in error and "is not the scene run" in error and not (tmp_path / "bundle").exists()


def test_the_export_stage_given_the_runs_scene_writes_its_reference(trained_run, background, tmp_path):
    """What vc-compile's export does with its scene (and vc-export --scene): here a stand-in for the test run's scene,
    its hash the run's, its background the test scene's, and a zone."""
    from types import SimpleNamespace

    from vc.scenes.schema import ZoneSpec
    from vc.stages.config import ExportSettings
    from vc.stages.export import export

    write_image(tmp_path / "background.png", background)
    door = ZoneSpec(name="door", frame="image", polygon=[[10, 10], [40, 10], [40, 40]])
    scene = SimpleNamespace(content_hash="f" * 64, image_path=tmp_path / "background.png", name="flat",
                            path=tmp_path / "scene.yaml", camera_response=lambda: SimpleNamespace(response=SRGB),
                            video_path=None, zones=(door,))
    result = export(trained_run, tmp_path / "bundle", ExportSettings(precision="fp32", eval_samples=0),
                    show_progress=False, scene=scene)
    entry = result.manifest["reference"]
    assert entry["background"] == REFERENCE_MEMBER and entry["cells"] == [32, 16] and entry["cell_px"] == 4
    assert entry["background_sha256"] == sha256((tmp_path / "bundle" / REFERENCE_MEMBER).read_bytes())
    assert result.bundle.reference.fitness(background).state == fit.OK
    # the scene's zones travel with it (docs/serve.md)
    assert [(zone.name, zone.frame, len(zone.polygon)) for zone in result.bundle.zones] == [("door", "image", 3)]


def test_a_scenes_reference_is_its_background_through_its_response():
    from vc.io import read_image
    from vc.model.export import scene_reference
    from vc.scenes.loader import load_scene

    scene = load_scene(REPO / "examples" / "scenes" / "demo" / "scene.yaml")
    reference = scene_reference(scene)
    background = read_image(scene.image_path)
    assert reference.cells.shape == (background.shape[0] // reference.cell_px,
                                     background.shape[1] // reference.cell_px, 3)
    assert reference.fitness(background).state == fit.OK


# Real cameras (development data, skipped when absent): every real frame stays ok, the conditions read as named.

def _pets_frames(numbers: set[int]) -> dict[int, np.ndarray]:
    import cv2

    capture, frames = cv2.VideoCapture(str(PETS_DATA / "vtest.avi")), {}
    for number in range(1, max(numbers) + 1):
        ok, bgr = capture.read()
        assert ok
        if number in numbers:
            frames[number] = np.ascontiguousarray(bgr[:, :, ::-1])
    return frames


@pytest.fixture(scope="module")
def pets(pets_data) -> tuple[SceneReference, list[np.ndarray]]:
    from vc.io import read_image

    frames = _pets_frames(set(range(1, 401, 40)))
    return SceneReference.of_background(read_image(pets_data / "background.png"), DECODE), list(frames.values())


@pytest.fixture(scope="module")
def tud() -> tuple[SceneReference, list[np.ndarray]]:
    """TUD-Stadtmitte has no bundle: its reference is the median of its frames, as a user would make it."""
    from vc.io import read_image

    paths = sorted(TUD_FRAMES.glob("*.png"))
    if not paths:
        pytest.skip(f"TUD-Stadtmitte frames not found at {TUD_FRAMES} (development data, not shipped)")
    frames = [read_image(path) for path in paths]
    median = np.median(np.stack(frames), axis=0).round().astype(np.uint8)
    return SceneReference.of_background(median, DECODE), frames[::18]


REAL_CONDITIONS = {
    "as recorded": (lambda image: image, fit.OK),
    "black": (np.zeros_like, fit.COVERED),
    "noise": (lambda image: np.random.default_rng(1).integers(0, 256, image.shape, dtype=np.uint8), fit.COVERED),
    "-2 stops": (lambda image: exposed(image, -2), fit.DARK),
    "-3 stops": (lambda image: exposed(image, -3), fit.DARK),
    "+2 stops": (lambda image: exposed(image, 2), fit.OVEREXPOSED),
    "white balance warm": (lambda image: gains(image, 1.25, 0.8), fit.CHANGED),
    "IR monochrome": (monochrome, fit.CHANGED),
    "blur sigma 2": (lambda image: blurred(image, 2), fit.BLURRED),
    "blur sigma 4": (lambda image: blurred(image, 4), fit.BLURRED),
    "shifted 12 px": (lambda image: shifted(image, 12, 0), fit.MOVED),
}


@pytest.mark.parametrize("camera", ["pets", "tud"])
@pytest.mark.parametrize("condition", list(REAL_CONDITIONS))
def test_real_frames_are_ok_and_their_conditions_read_as_named(request, camera, condition):
    reference, frames = request.getfixturevalue(camera)
    change, expected = REAL_CONDITIONS[condition]
    states = [reference.fitness(change(frame)).state for frame in frames]
    assert states == [expected] * len(frames)


# Compiled over the camera's range: what the bundle saw in training is fit (docs/decisions/0014-camera-range.md).

#: The fit range of a bundle compiled over the default camera range, as vc-export measured it on PETS09.
COMPILED_RANGE = fit.FitRange(dark_stops=3.21, overexposed_stops=1.3, blurred_sharpness=0.04, colour_cast_stops=0.91,
                              monochrome=True, veil_share=1.0, noise_codes=68.4, changed_agreement=0.3)


def _camera(condition) -> np.ndarray:
    """A function of a frame: the frame under one camera-range ``condition`` (vc.model.camera_range)."""
    from vc.calibration.noise import NoiseModel
    from vc.model.camera_range import CameraLife, CameraRange

    life = CameraLife(CameraRange(), SRGB, NoiseModel(0.0, 0.0), region_scale=1.0)
    return lambda image: life.render(image, condition, np.random.default_rng(0))


def _weather():
    from vc.model.camera_range import Condition

    return {"gain noise": Condition(gain_noise=0.15, shot_share=0.75),
            "fog": Condition(veil_transmission=0.4, airlight=2.0),
            "snow": Condition(precipitation=(0.004, 1.0, 3.0, 5.0, 0.8)),
            "defocus": Condition(defocus_px=3.0)}


@pytest.mark.parametrize(("change", "expected"), [
    (lambda image: exposed(image, -2), fit.OK), (lambda image: exposed(image, -3), fit.OK),
    (lambda image: linear_gains(image, 1.25, 0.8), fit.OK), (lambda image: linear_gains(image, 0.8, 1.25), fit.OK),
    (monochrome, fit.OK), (lambda image: blurred(image, 2), fit.OK),
    (lambda image: exposed(image, -4), fit.DARK), (lambda image: exposed(image, 2), fit.OVEREXPOSED),
    (np.zeros_like, fit.COVERED), (lambda image: np.full_like(image, 128), fit.COVERED),
])
def test_a_bundle_compiled_over_the_camera_range_takes_its_range_as_fit(background, change, expected):
    reference = SceneReference.of_background(background, DECODE)
    assert reference.fitness(change(background), COMPILED_RANGE).state == expected


@pytest.mark.parametrize("weather", ["gain noise", "fog", "snow", "defocus"])
def test_noise_fog_snow_and_defocus_are_fit_as_far_as_the_bundle_was_compiled_for_them(background, weather):
    """A bundle compiled over the range sees through them; one compiled for the background's one look never saw
    them: its fitness withholds the frame (the noisy one by its noise, the veiled one by its veil)."""
    reference = SceneReference.of_background(background, DECODE)
    frame = _camera(_weather()[weather])(background)
    compiled = reference.fitness(frame, COMPILED_RANGE)
    assert compiled.state == fit.OK, compiled
    one_look = reference.fitness(frame)
    expected = {"gain noise": "noise of", "fog": "stops against", "defocus": "fine detail"}  # fog: dark, first
    if weather in expected:
        assert one_look.unfit and expected[weather] in one_look.reason, one_look
    if weather == "fog":
        assert 0.4 < compiled.veil < 0.9 and abs(compiled.exposure_stops - math.log2(0.4)) < 0.3
    if weather == "gain noise":
        assert 30 < compiled.noise_codes < 50  # 0.15 of the code range is 38 codes at mid-grey


def test_real_frames_read_no_veil_and_their_sensor_s_noise(pets):
    reference, frames = pets
    for frame in frames:
        fitness = reference.fitness(frame, COMPILED_RANGE)
        assert fitness.state == fit.OK and fitness.veil == 0.0 and fitness.noise_codes < 3.0


def test_another_view_stays_changed_whatever_the_range(background):
    """What the range widens is the look of the same view: another one still matches nothing."""
    reference = SceneReference.of_background(background, DECODE)
    other = scene_background(seed=8)
    for frame in (other, _camera(_weather()["gain noise"])(other), _camera(_weather()["fog"])(other)):
        fitness = reference.fitness(frame, COMPILED_RANGE)
        assert fitness.unfit and fitness.correlation < fit.SAME_VIEW_CORRELATION, fitness


def test_a_patchy_fog_keeps_the_view_s_structure_where_its_light_no_longer_correlates(background):
    """COCO-C's fog: an airlight varying over the view more than the scene's light does (codes ``(x + 2.5 f) /
    3.5``, ``f`` a smooth field over [0, 1]). The light over the cells no longer follows the background's, the
    structure under it still does: the view is not taken for another
    (docs/decisions/0017-bright-and-veiled-frames.md)."""
    reference = SceneReference.of_background(background, DECODE)
    height, width = background.shape[:2]
    field = _smooth(np.random.default_rng(3), (height, width), width / 4)
    field = (field - field.min()) / (field.max() - field.min())
    fogged = np.clip((background / 255.0 + 2.5 * field[..., None]) / 3.5 * 255.0, 0, 255).round().astype(np.uint8)
    cells = fit.cell_means(fogged, reference.cell_px) @ fit.LUMA
    assert np.corrcoef(cells.ravel(), reference.derived["luma"].ravel())[0, 1] < fit.SAME_VIEW_CORRELATION
    fitness = reference.fitness(fogged, COMPILED_RANGE)
    assert fitness.correlation >= fit.SAME_VIEW_CORRELATION and "another view" not in fitness.reason, fitness
    mirrored = reference.fitness(np.ascontiguousarray(fogged[:, ::-1]), COMPILED_RANGE)
    assert mirrored.correlation < fit.SAME_VIEW_CORRELATION and mirrored.unfit, mirrored


def _fogged(frame: np.ndarray, seed: int) -> np.ndarray:
    """COCO-C's fog at severity 3, as it is made: codes ``(x + 2.5 f) / 3.5``, ``f`` a smooth field over [0, 1]."""
    height, width = frame.shape[:2]
    field = _smooth(np.random.default_rng(seed), (height, width), width / 8)
    field = (field - field.min()) / (field.max() - field.min())
    return np.clip((frame / 255.0 + 2.5 * field[..., None]) / 3.5 * 255.0, 0, 255).round().astype(np.uint8)


def test_a_fog_whose_light_fails_the_cells_keeps_the_view_and_a_view_mostly_replaced_does_not(pets):
    """Two tests of a changed view, both failed: the cells' light and the view's structure. A patchy fog fails the
    first only; a view 80 % replaced by another, both (docs/decisions/0017-bright-and-veiled-frames.md)."""
    reference, frames = pets
    height, width = frames[0].shape[:2]
    other = scene_background((width, height), seed=8)
    for index, frame in enumerate(frames[:4]):
        fogged = reference.fitness(_fogged(frame, index), COMPILED_RANGE)
        assert fogged.correlation >= fit.KEPT_VIEW_CORRELATION and fogged.state == fit.OK, fogged
        replaced = frame.copy()
        replaced[:, :int(0.8 * width)] = other[:, :int(0.8 * width)]
        fitness = reference.fitness(replaced, COMPILED_RANGE)
        assert fitness.state == fit.CHANGED and fitness.matching < COMPILED_RANGE.changed_agreement, fitness
    assert any(reference.fitness(_fogged(frame, index), COMPILED_RANGE).matching < COMPILED_RANGE.changed_agreement
               for index, frame in enumerate(frames[:4]))  # the cells' light alone would have withheld it


def test_colour_taken_away_toward_grey_is_not_a_cast_and_a_white_balance_still_is(background):
    """Snow, fog and a veil take colour away toward grey: every chromaticity moves toward neutral, their centre with
    them, and no white balance changed (docs/decisions/0017-bright-and-veiled-frames.md)."""
    earthy = linear_gains(background, 1.4, 0.6)  # a ground of one colour: its chromaticities' centre is not grey
    reference = SceneReference.of_background(earthy, DECODE)
    linear = SRGB.decode(earthy)
    grey = (linear @ fit.LUMA)[..., None]
    for kept in (0.8, 0.5):
        greyer = reference.fitness(SRGB.encode(kept * linear + (1 - kept) * grey))
        assert greyer.colour_cast_stops < 0.15 and abs(greyer.colour_left - kept) < 0.2, greyer
    warm = reference.fitness(linear_gains(earthy, 1.25, 0.8))
    assert warm.colour_cast_stops > 0.4 and warm.colour_left > 0.8, warm  # log2 1.25 and 0.8: 0.45


def test_a_white_balance_beyond_the_range_is_read_through_a_veil(background):
    """The cast is the smaller of the frame's with the veil taken off and as it is; a white balance shows in both."""
    from vc.model.camera_range import Condition

    reference = SceneReference.of_background(background, DECODE)
    veil = {"veil_transmission": 0.5, "airlight": 2.0}
    assert reference.fitness(_camera(Condition(**veil))(background), COMPILED_RANGE).state == fit.OK
    cast = reference.fitness(_camera(Condition(gains=(2.0, 1.0, 0.5), **veil))(background), COMPILED_RANGE)
    assert cast.state == fit.CHANGED and "colour cast" in cast.reason and cast.veil > 0, cast


def test_every_veil_the_range_renders_is_within_its_measured_bound(background):
    """The veil's share is read through clipping, so the bound is measured over the range's veils, not at one end."""
    from vc.model.camera_range import AIRLIGHT_RATIO, CameraRange, Condition, fit_range_of

    reference = SceneReference.of_background(background, DECODE)
    spec = CameraRange()
    measured = fit_range_of(spec, reference, background, SRGB)
    for transmission in np.linspace(spec.veil_transmission, 0.9, 4):
        for airlight in np.linspace(*AIRLIGHT_RATIO, 3):
            frame = _camera(Condition(veil_transmission=float(transmission), airlight=float(airlight)))(background)
            fitness = reference.fitness(frame, measured)
            assert fitness.veil <= measured.veil_share, (transmission, airlight, fitness)


def test_the_fit_range_is_measured_on_the_background_at_the_camera_range_s_ends(background):
    from vc.model.camera_range import CameraRange, fit_range_of

    reference = SceneReference.of_background(background, DECODE)
    assert fit_range_of(None, reference, background, SRGB) == fit.FitRange()
    measured = fit_range_of(CameraRange(), reference, background, SRGB)
    assert 3.0 <= measured.dark_stops <= 3.5 and measured.overexposed_stops == fit.OVEREXPOSED_STOPS
    assert measured.colour_cast_stops > fit.COLOUR_CAST_STOPS and measured.monochrome
    assert measured.blurred_sharpness < fit.BLURRED_SHARPNESS
    assert measured.noise_codes > 40 and measured.veil_share >= fit.VEIL_SHARE
    drifting = fit_range_of(CameraRange(), reference, background, SRGB, [exposed(background, 0.4), background])
    assert drifting.overexposed_stops == pytest.approx(measured.overexposed_stops + 0.4, abs=0.05)
    assert drifting.dark_stops == measured.dark_stops  # the frames never drifted darker
    assert fit.CHANGED_AGREEMENT > measured.changed_agreement >= 0.3
    night_less = fit_range_of(CameraRange(night_ir=0.0, blurred=0.0, exposure_stops=(-1.0, 0.5), noisy=0.0,
                                          veiled=0.0, precipitation=0.0), reference, background, SRGB)
    assert not night_less.monochrome and night_less.blurred_sharpness == fit.BLURRED_SHARPNESS
    assert night_less.dark_stops == fit.DARK_STOPS  # never tighter than the background's own look
    assert (night_less.noise_codes, night_less.veil_share, night_less.changed_agreement) == (
        fit.NOISE_CODES, fit.VEIL_SHARE, fit.CHANGED_AGREEMENT)


def test_a_bundle_compiled_for_gain_noise_takes_more_noise_than_its_range_as_fit(background):
    """Its networks read people through 1.6 times the noise of its highest gain (docs/decisions/0022): such a frame
    is fit, a lost signal's noise still covered."""
    from vc.model.camera_range import FIT_NOISE_MARGIN, CameraRange, fit_range_of

    reference = SceneReference.of_background(background, DECODE)
    measured = fit_range_of(CameraRange(), reference, background, SRGB)
    heaviest = measured.noise_codes / FIT_NOISE_MARGIN  # the range's highest gain, as the fitness reads it
    noisy = np.clip(background + np.random.default_rng(1).normal(0, 1.6 * heaviest, background.shape), 0, 255)
    fitness = reference.fitness(noisy.round().astype(np.uint8), measured)
    assert fitness.state == fit.OK and fitness.noise_codes > 1.25 * heaviest, fitness
    lost_signal = np.random.default_rng(0).integers(0, 256, background.shape, dtype=np.uint8)
    assert reference.fitness(lost_signal, measured).state == fit.COVERED


def _with_fit_range(bundle: Path, background: np.ndarray, fit_range: object, output: Path) -> Path:
    manifest, files = _bundle_files(bundle)
    for region in manifest["regions"]:
        region["decode"]["centre_threshold"] = 0.001
    manifest, files = with_reference(manifest, files, SceneReference.of_background(background, DECODE),
                                     "the test scene's background", COMPILED_RANGE)
    manifest["reference"]["fit_range"] = fit_range
    write_bundle(manifest, files, output, as_zip=False)
    return output


def test_a_bundle_carries_its_fit_range_and_runs_frames_within_it(bundle, background, tmp_path):
    folder = _with_fit_range(bundle, background, COMPILED_RANGE.to_dict(), tmp_path / "bundle")
    with Runtime(folder, threads=1) as runtime:
        assert runtime.bundle.fit_range == COMPILED_RANGE
        result = runtime.run(exposed(background, -3))
        assert result.fitness.state == fit.OK and not result.suppressed and result.people
        assert runtime.run(np.zeros_like(background)).suppressed


@pytest.mark.parametrize(("value", "message"), [
    ({"dark_stops": -1}, "dark_stops must be a finite number"), ({"dark_stops": "far"}, "dark_stops"),
    ({"monochrome": "yes"}, "monochrome must be true or false"), ({"tolerance": 1}, "unknown field"),
    ([1, 2], "expected a mapping"),
])
def test_a_bad_fit_range_is_refused_by_name(bundle, background, tmp_path, value, message):
    folder = _with_fit_range(bundle, background, value, tmp_path / "bundle")
    with pytest.raises(InputError, match=f"reference.fit_range.*{message}"):
        load_bundle(folder)


def test_translated_moves_the_view_back():
    frame = np.random.default_rng(0).integers(0, 256, (40, 60, 3), dtype=np.uint8)
    for dx, dy in ((3, 0), (-5, 7), (0, -9), (12, 12)):
        assert np.array_equal(translated(shifted(frame, dx, dy), (dx, dy))[12:-12, 12:-12], frame[12:-12, 12:-12])
    assert translated(frame, (0, 0)) is frame
    with pytest.raises(ValueError, match="leaves nothing"):
        translated(frame, (60, 0))


def test_a_nudged_view_is_registered_and_its_people_reported_where_they_stand(referenced_bundle, background):
    frame = background.copy()
    frame[24:40, 60:66] = (40, 50, 60)  # someone standing there
    with Runtime(referenced_bundle, threads=1) as runtime:
        still = runtime.run(frame)
    with Runtime(referenced_bundle, threads=1) as runtime:
        nudged = runtime.run(shifted(frame, 6, -3))
        assert nudged.fitness.state == fit.OK and nudged.fitness.registered_px == (6, -3)
        assert nudged.fitness.to_dict()["registered_px"] == [6, -3] and runtime.registration == Registration(6, -3)
        assert len(nudged.people) == len(still.people)
        # where they stand, as the camera shows them: boxes clipped to the frame (0020) after the move
        height, width = frame.shape[:2]
        expected = np.array(sorted(np.clip(person.box + [6, -3, 6, -3], -0.5, [width - 0.5, height - 0.5] * 2).tolist()
                                   for person in still.people))
        assert np.allclose(sorted(person.box.tolist() for person in nudged.people), expected, atol=1.0)
        assert runtime.run(shifted(frame, 6, -3)).fitness.registered_px == (6, -3)  # kept for the next frame
        assert runtime.run(frame).fitness.registered_px is None and runtime.registration.still  # moved back


def test_a_rolled_view_is_registered_and_its_people_reported_where_they_stand(referenced_bundle, background):
    import cv2

    frame = background.copy()
    frame[24:40, 60:66] = (40, 50, 60)  # someone standing there
    height, width = frame.shape[:2]
    knocked = Registration(2, -1, 2.0)  # a camera knocked: its view moved and turned 2 degrees
    rolled = cv2.warpAffine(frame, knocked.matrix((width, height)), (width, height), flags=cv2.INTER_LINEAR,
                            borderMode=cv2.BORDER_REPLICATE)
    with Runtime(referenced_bundle, threads=1) as runtime:
        still = runtime.run(frame)
    with Runtime(referenced_bundle, threads=1) as runtime:
        seen = runtime.run(rolled)
        assert seen.fitness.state == fit.OK and seen.fitness.registered_roll_deg == pytest.approx(2.0, abs=0.5)
        assert seen.fitness.to_dict()["registered_roll_deg"] == pytest.approx(2.0, abs=0.5)
        assert np.abs(np.subtract(runtime.registration.shift, knocked.shift)).max() <= 1
        assert runtime.fitness_summary([still.fitness, seen.fitness])["registered_frames"] == 1
        # the strongest person where the camera shows them: the box's centre carried by the roll and the move (the
        # test network's faint peaks, which it reports too, change with the view's pixels)
        x0, y0, x1, y1 = max(still.people, key=lambda person: person.score).box
        expected = knocked.forward(np.array([[(x0 + x1) / 2, (y0 + y1) / 2]]), (width, height))[0]
        centres = np.array([[(x0 + x1) / 2, (y0 + y1) / 2] for x0, y0, x1, y1 in (p.box for p in seen.people)])
        assert np.linalg.norm(centres - expected, axis=1).min() < 1.0  # 2.3 px off if left where it was found
        assert runtime.run(frame).fitness.registered_roll_deg is None and runtime.registration.still  # turned back
        runtime.run(rolled)
        runtime.reset()  # another clip: the registration is forgotten, and found again on its first rolled frame
        assert runtime.registration.still and runtime.last_fitness is None
        assert runtime.run(rolled).fitness.registered_roll_deg == pytest.approx(2.0, abs=0.5)


def test_a_view_moved_beyond_the_bound_is_moved(referenced_bundle, background):
    reference = SceneReference.of_background(background, DECODE)
    assert reference.register(shifted(background, 5, 2)) == Registration(5, 2)
    assert reference.register(shifted(background, 5, 2), bound_px=4) is None
    assert reference.register(np.random.default_rng(3).integers(0, 256, background.shape, dtype=np.uint8)) is None
    with Runtime(referenced_bundle, threads=1) as runtime:
        result = runtime.run(shifted(background, 5, 2))
        assert result.fitness.registered_px == (5, 2)


@pytest.mark.parametrize("move", [(3, 0), (12, 0), (-7, 5), (20, -10)])
def test_pets09_views_moved_within_the_bound_are_registered_to_the_pixel(pets, move):
    reference, frames = pets
    for frame in frames[:3]:
        assert reference.register(shifted(frame, *move)) == Registration(*move)
    assert reference.register(shifted(frames[0], 30, 0)) is None
