"""The decoder on the heat maps a network can emit at its edges: empty, constant, saturated, single-cell spikes,
ties, people at the map border, extreme expected heights. No input in range makes it crash or emit NaN or inf."""

from __future__ import annotations

import numpy as np
from hard_case_settings import PROPERTY
from hypothesis import given
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from vc.deploy.decode import DecodeConfig, decode
from vc.deploy.heatmaps import CENTRE_CHANNEL, HEATMAP_CHANNELS

HEIGHT, WIDTH = 12, 16  # cells


def _check(people, heatmaps: np.ndarray, config: DecodeConfig) -> None:
    stride = config.stride
    assert len(people) <= config.max_people
    for person in people:
        values = np.concatenate([[person.score], person.centre, person.keypoints.ravel(), person.box])
        assert np.isfinite(values).all()
        x0, y0, x1, y1 = person.box
        assert x0 < x1 and y0 < y1
        assert -stride <= person.centre[0] <= WIDTH * stride and -stride <= person.centre[1] <= HEIGHT * stride
        assert person.mask_cells.shape == heatmaps.shape[1:]


kinds = st.sampled_from(["zeros", "constant", "saturated", "spikes", "random", "ties"])


@st.composite
def heatmaps(draw) -> np.ndarray:
    kind = draw(kinds)
    maps = np.zeros((HEATMAP_CHANNELS, HEIGHT, WIDTH), np.float32)
    if kind == "constant":
        maps[:] = draw(st.floats(0.0, 1.0, width=32))
    elif kind == "saturated":
        maps[:] = 1.0
    elif kind == "random":
        maps[:] = draw(arrays(np.float32, maps.shape, elements=st.floats(-1.0, 1.5, width=32)))
    elif kind in ("spikes", "ties"):
        cells = draw(st.lists(st.tuples(st.integers(0, HEIGHT - 1), st.integers(0, WIDTH - 1)), min_size=1,
                              max_size=8))
        level = draw(st.floats(0.3125, 1.0, width=32))
        for row, column in cells:  # corners and edges included: people at the map border
            maps[:, row, column] = level if kind == "ties" else draw(st.floats(0.0, 1.0, width=32))
    return maps


@PROPERTY
@given(maps=heatmaps(), height_px=st.floats(1e-3, 1e4), threshold=st.floats(0.0, 1.0))
def test_decode_never_emits_nan_or_inf(maps, height_px, threshold):
    config = DecodeConfig(centre_threshold=threshold)
    expected = np.full((HEIGHT, WIDTH), height_px)
    _check(decode(maps, config, expected), maps, config)


@PROPERTY
@given(maps=heatmaps(), reach=st.floats(0.0, 2.0), separation=st.floats(0.0, 2.0))
def test_decode_settings_at_their_edges_stay_finite(maps, reach, separation):
    config = DecodeConfig(reach_sideways=reach, min_centre_separation=separation, max_people=3)
    _check(decode(maps, config), maps, config)


def test_a_plateau_of_ties_is_one_person_not_many():
    maps = np.zeros((HEATMAP_CHANNELS, HEIGHT, WIDTH), np.float32)
    maps[CENTRE_CHANNEL, 4:7, 5:9] = 0.8  # a flat-topped peak
    assert len(decode(maps, DecodeConfig(), np.full((HEIGHT, WIDTH), 40.0))) == 1
