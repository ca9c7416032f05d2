"""The C decoder (vc.deploy.native) against numpy's, the reference: on random, degenerate and hostile heat maps the
same people read (:func:`vc.deploy.decode.decode_readings`; step 5's rules over them are numpy's for both): count
equal, boxes, centres and keypoints within 1e-3 px, scores, handedness and masks equal; or the same refusal.
tests/test_native_sanitizers.py runs this module again on an AddressSanitizer and UndefinedBehaviorSanitizer build
(:envvar:`VC_DECODER_LIBRARY`)."""

from __future__ import annotations

import os

import numpy as np
import pytest
from hard_case_settings import PROPERTY
from hypothesis import given
from hypothesis import strategies as st

from vc.deploy import native
from vc.deploy.decode import DecodeConfig, decode_readings
from vc.deploy.heatmaps import (
    CENTRE_OFFSET_CHANNELS,
    HEAD_CHANNEL,
    HEAD_CHANNELS,
    LAYOUTS,
    SIZE_CHANNEL,
    SIZE_UNIT_CELLS,
)

pytestmark = pytest.mark.skipif(not native.available(), reason=f"the C decoder is not built ({native.LIBRARY}: "
                                                               f"make install builds it)")

TOLERANCE_PX = 1e-3


def both(maps: np.ndarray, config: DecodeConfig, heights: np.ndarray | None, weak_above: float | None):
    """Both decoders' people, or both refusals' messages (one raising and the other not fails)."""
    outcomes = []
    for decoder in (decode_readings, native.decode_readings):
        try:
            outcomes.append(decoder(maps, config, heights, weak_above))
        except ValueError as error:
            outcomes.append(str(error))
    return outcomes


def assert_same(maps: np.ndarray, config: DecodeConfig | None = None, heights: np.ndarray | None = None,
                weak_above: float | None = None) -> int:
    reference, ours = both(maps, config or DecodeConfig(), heights, weak_above)
    if isinstance(reference, str) or isinstance(ours, str):
        assert reference == ours
        return 0
    assert len(ours) == len(reference)
    for a, b in zip(reference, ours, strict=True):
        assert a.score == b.score and a.weak == b.weak and a.head_found == b.head_found
        np.testing.assert_allclose(b.centre, a.centre, rtol=0, atol=TOLERANCE_PX)
        np.testing.assert_allclose(b.box, a.box, rtol=0, atol=TOLERANCE_PX)
        np.testing.assert_allclose(b.keypoints[:, :2], a.keypoints[:, :2], rtol=0, atol=TOLERANCE_PX)
        np.testing.assert_array_equal(b.keypoints[:, 2], a.keypoints[:, 2])
        np.testing.assert_array_equal(b.pair_handedness, a.pair_handedness)
        np.testing.assert_array_equal(b.mask_cells, a.mask_cells)
    return len(ours)


def blobs(rng: np.random.Generator, channels: int, height: int, width: int, people: int) -> np.ndarray:
    """Heat maps shaped like a network's: a Gaussian centre, keypoints and mask per person, offsets towards the
    centres, handedness of either sign, and noise."""
    rows, columns = np.mgrid[0:height, 0:width]
    maps = (rng.random((channels, height, width)) * 0.1).astype(np.float32)
    for _ in range(people):
        x, y, size = rng.uniform(0, width), rng.uniform(0, height), rng.uniform(2, 12)
        for channel in range(min(channels, 19)):
            dy = 0.0 if channel in (0, 18) else rng.uniform(-0.45, 0.45) * size
            dx = rng.uniform(-0.1, 0.1) * size
            spread = size * (0.35 if channel == 18 else 0.08)
            bump = np.exp(-((columns - x - dx) ** 2 + (rows - y - dy) ** 2) / (2 * spread**2))
            maps[channel] = np.maximum(maps[channel], rng.uniform(0.4, 1.0) * bump)
        maps[19:27] += (rng.choice([-1.0, 1.0], 8)[:, None, None] * (maps[18] > 0.5)).astype(np.float32)
        if channels >= CENTRE_OFFSET_CHANNELS.stop:
            maps[27] += ((x - columns) / size * (maps[18] > 0.5)).astype(np.float32)
            maps[28] += ((y - rows) / size * (maps[18] > 0.5)).astype(np.float32)
        if channels == HEAD_CHANNELS:  # a head 0.4 heights above the centre, the person's log size over them
            head = np.exp(-((columns - x) ** 2 + (rows - y + 0.4 * size) ** 2) / (2 * (0.05 * size + 0.75) ** 2))
            maps[HEAD_CHANNEL] = np.maximum(maps[HEAD_CHANNEL], rng.uniform(0.4, 1.0) * head)
            maps[SIZE_CHANNEL] = np.where(maps[18] > 0.5, np.log(size / SIZE_UNIT_CELLS), maps[SIZE_CHANNEL])
    return maps


settings_of_the_decoder = st.fixed_dictionaries({
    "centre_threshold": st.sampled_from([0.3, 0.1, 0.6]),
    "min_centre_separation": st.sampled_from([0.15, 0.0, 1.0]),
    "vote_support": st.sampled_from([0.15, 0.01, 0.5]),
    "vote_separation": st.sampled_from([None, 0.3]),
    "max_people": st.sampled_from([100, 3, 0]),
    "reach_sideways": st.sampled_from([0.2, 0.0, 2.0]),
})


@st.composite
def cases(draw):
    """Heat maps (float32, one of the layouts) of one kind, expected heights or none, a weak floor or none."""
    seed = draw(st.integers(0, 2**32 - 1))
    rng = np.random.default_rng(seed)
    channels = draw(st.sampled_from(LAYOUTS))
    height, width = draw(st.integers(1, 40)), draw(st.integers(1, 60))
    kind = draw(st.sampled_from(["blobs", "random", "sparse", "zeros", "constant", "one cell", "huge", "ties"]))
    if kind == "blobs":
        maps = blobs(rng, channels, height, width, draw(st.integers(1, 12)))
    elif kind == "random":
        maps = (rng.random((channels, height, width)) ** draw(st.sampled_from([1, 4, 8]))).astype(np.float32)
        maps[CENTRE_OFFSET_CHANNELS] = rng.normal(0, 0.3, maps[CENTRE_OFFSET_CHANNELS].shape)
    elif kind == "sparse":
        maps = np.where(rng.random((channels, height, width)) < 0.05, 1.0, 0.0).astype(np.float32)
    elif kind == "zeros":
        maps = np.zeros((channels, height, width), np.float32)
    elif kind == "constant":
        maps = np.full((channels, height, width), draw(st.floats(-2.0, 2.0, width=32)), np.float32)
    elif kind == "one cell":
        maps = np.zeros((channels, height, width), np.float32)
        maps[:, rng.integers(height), rng.integers(width)] = draw(st.floats(0.0, 1.0, width=32))
    elif kind == "huge":  # the largest finite float32 values, of both signs: float32 arithmetic overflows
        maps = rng.choice(np.array([-3.4e38, 0.0, 1.0, 3.4e38], np.float32), (channels, height, width))
    else:  # equal values on a lattice of cells: every tie the decoder breaks
        maps = np.zeros((channels, height, width), np.float32)
        maps[:, ::2, ::3] = 0.75
    heights = draw(st.sampled_from(["camera", "constant", "none", "extreme"]))
    expected = {"camera": lambda: np.linspace(10, 80, height, dtype=np.float32)[:, None].repeat(width, 1),
                "constant": lambda: np.full((height, width), 40.0, np.float32),
                "none": lambda: None,
                "extreme": lambda: rng.choice(np.array([1e-3, 1.0, 1e5], np.float32), (height, width))}[heights]()
    return maps, expected, draw(st.sampled_from([None, 0.1, 0.3])), draw(settings_of_the_decoder)


@PROPERTY
@given(case=cases())
def test_the_c_decoder_reports_the_same_people_as_numpy(case):
    maps, heights, weak_above, settings = case
    assert_same(maps, DecodeConfig(**settings), heights, weak_above)


@PROPERTY
@given(case=cases(), value=st.sampled_from([np.nan, np.inf, -np.inf]), where=st.integers(0, 2**31))
def test_both_decoders_refuse_a_non_finite_value(case, value, where):
    maps, heights, weak_above, settings = case
    maps.reshape(-1)[where % maps.size] = value
    with pytest.raises(ValueError, match="NaN or infinite"):
        native.decode(maps, DecodeConfig(**settings), heights, weak_above)
    assert_same(maps, DecodeConfig(**settings), heights, weak_above)


@pytest.mark.parametrize("heights", [0.0, -1.0, np.nan, np.inf, 2e5])
def test_both_decoders_refuse_expected_heights_out_of_range(heights):
    maps = blobs(np.random.default_rng(0), LAYOUTS[-1], 20, 30, 3)
    expected = np.full((20, 30), 40.0, np.float32)
    expected[5, 7] = heights
    with pytest.raises(ValueError, match="expected heights"):
        native.decode(maps, DecodeConfig(), expected)
    assert_same(maps, DecodeConfig(), expected)


@pytest.mark.parametrize("channels", [0, 19, 28, 40])
def test_both_decoders_refuse_heat_maps_of_no_layout(channels):
    maps = np.zeros((channels, 8, 8), np.float32)
    with pytest.raises(ValueError, match="channels"):
        native.decode(maps)
    assert_same(maps)


@pytest.mark.parametrize("shape", [(1, 1), (0, 5), (5, 0), (1, 20_000), (3_000, 2), (256, 256)])
def test_heat_maps_of_any_size(shape):
    """One cell, none, a line, a column and a large map: the same people, no read outside the maps."""
    maps = blobs(np.random.default_rng(sum(shape)), LAYOUTS[1], *shape, 40) if 0 not in shape else \
        np.zeros((LAYOUTS[1], *shape), np.float32)
    assert_same(maps, DecodeConfig(), np.full(shape, 30.0, np.float32), 0.1)


def test_a_crowd_of_people_on_a_camera_is_decoded_alike():
    """A busy frame: most of the decoder's paths (votes, shared keypoints, weak people) on each person."""
    rng = np.random.default_rng(7)
    heights = np.linspace(15, 60, 36, dtype=np.float32)[:, None].repeat(148, 1)
    assert sum(assert_same(blobs(rng, LAYOUTS[-1], 36, 148, 25), DecodeConfig(), heights, 0.1)
               for _ in range(20)) > 100


def test_the_library_loaded_is_the_one_named():
    """Under tests/test_native_sanitizers.py the sanitized build is the one these tests run."""
    named = os.environ.get(native.LIBRARY_VARIABLE)
    assert native.library_path() == (native.LIBRARY if not named else native.Path(named))


@pytest.mark.parametrize("edit", ["truncated", "another version", "a value missing", "a word for a number",
                                  "a height out of range", "one value too many", "empty"])
def test_a_damaged_decoder_file_is_refused_with_its_line(tmp_path, edit):
    lines = small_decoder_file().decode().splitlines()
    damaged = {"truncated": lambda: lines[:len(lines) // 2],
               "another version": lambda: ["visual-compiler-decoder 2", *lines[1:]],
               "a value missing": lambda: [lines[0], "frame_size 768", *lines[2:]],
               "a word for a number": lambda: [line.replace("stride 4", "stride four") for line in lines],
               "a height out of range": lambda: [*lines[:-2], "0 " + lines[-2], lines[-1]],
               "one value too many": lambda: [*lines, "end"],
               "empty": lambda: []}[edit]()
    path = tmp_path / "decoder.txt"
    path.write_text("\n".join(damaged) + "\n")
    with pytest.raises(ValueError, match=r"line \d+: the decoder file is malformed"):
        native.read_decoder_file(path)


def small_decoder_file() -> bytes:
    """The decoder file of a two-region bundle's manifest and height maps (no networks: the file does not hold
    them)."""
    import io

    from vc.deploy.decoder_file import decoder_file

    files, regions = {}, []
    for index, shape in enumerate([(6, 9), (3, 4)]):
        buffer = io.BytesIO()
        np.save(buffer, np.linspace(12.5, 60.25, np.prod(shape), dtype=np.float32).reshape(shape))
        files[f"models/r{index}.heights.npy"] = buffer.getvalue()
        regions.append({"name": f"r{index}", "crop_window": [0, 40 * index, 36, 24], "input_size": [36, 24],
                        "decode": {"vote_separation": 0.25 if index else None},
                        "expected_height": f"models/r{index}.heights.npy"})
    manifest = {"frame_size": [64, 48], "output": {"channels": ["map"] * LAYOUTS[-1]}, "regions": regions}
    return decoder_file(manifest, files)


def test_a_decoder_file_reads_back_exactly_in_c(tmp_path):
    (tmp_path / "decoder.txt").write_bytes(small_decoder_file())
    frame_size, regions = native.read_decoder_file(tmp_path / "decoder.txt")
    assert frame_size == (64, 48) and [region.name for region in regions] == ["r0", "r1"]
    assert regions[1].config == DecodeConfig(vote_separation=0.25) and regions[0].config == DecodeConfig()
    np.testing.assert_array_equal(regions[1].expected_height_px,
                                  np.linspace(12.5, 60.25, 12, dtype=np.float32).reshape(3, 4))


def test_a_missing_decoder_file_is_refused(tmp_path):
    with pytest.raises(ValueError, match="cannot be read"):
        native.read_decoder_file(tmp_path / "decoder.txt")
