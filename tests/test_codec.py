"""Codec round trip: encode labels as heat maps, decode them back (numpy decoder shared with deployment).

Issue 4's acceptance: keypoints come back within one output stride. Here they must come back far closer (the
decoder refines peaks to sub-cell precision), centres too, and the box takes the expected height.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from vc.deploy.decode import (
    LOWER_ANKLE_OFFSET,
    SETTLED_SWITCHES,
    UPRIGHT_OFFSETS,
    DecodeConfig,
    RetiredSetting,
    _keypoints,
    _median,
    _update_window_sums,
    _window_sums,
    decode,
    find_peaks,
    local_maxima,
    stored_decode_fields,
)
from vc.deploy.heatmaps import (
    ANATOMICAL_CHANNELS,
    CENTRE_CHANNEL,
    CENTRE_OFFSET_CHANNELS,
    FINE_CENTRE_CHANNELS,
    FINE_CHANNELS,
    HANDEDNESS_CHANNELS,
    HEAD_CHANNEL,
    HEATMAP_CHANNELS,
    KEYPOINT_CHANNELS,
    MASK_CHANNEL,
    OFFSET_CHANNELS,
    PAIRS,
    cells_to_fine,
    cells_to_input,
    fine_centre_channels,
    fine_centre_map,
    input_to_cells,
    swap_pairs,
)
from vc.model.codec import CodecConfig, encode
from vc.model.trainer import centre_map_settings

STRIDE = 4
WIDTH, HEIGHT = 256, 192
#: A standing person facing the camera (its left side on the image's right): COCO keypoints as fractions of its
#: height, relative to the centre (x right, y down), at the decoder's upright prior; both feet planted, so both
#: ankles where the lower one is.
BODY = np.c_[
    [0.0, 0.02, -0.02, 0.05, -0.05, 0.11, -0.11, 0.14, -0.14, 0.15, -0.15, 0.07, -0.07, 0.08, -0.08, 0.08, -0.08],
    np.r_[UPRIGHT_OFFSETS[:15], LOWER_ANKLE_OFFSET, LOWER_ANKLE_OFFSET],
]


def _person(centre: tuple[float, float], height: float, instance_id: int, hidden: tuple[int, ...] = (),
            facing_away: bool = False) -> dict:
    keypoints = np.asarray(centre) + BODY * [-1.0 if facing_away else 1.0, 1.0] * height
    visibility = np.full(17, 2)
    visibility[list(hidden)] = 1
    x0, y0 = centre[0] - 0.2 * height, centre[1] - 0.5 * height
    return {"center": list(centre), "keypoints": np.c_[keypoints, visibility].ravel().tolist(),
            "amodal_bbox": [x0, y0, 0.4 * height, height], "instance_id": instance_id,
            "left_is_image_left": [facing_away] * len(PAIRS)}


PEOPLE = [_person((60.3, 95.7), 100.0, 1), _person((150.8, 80.2), 70.0, 2, hidden=(3, 9), facing_away=True),
          _person((215.1, 110.6), 140.0, 3)]


def _instances(people: list[dict]) -> np.ndarray:
    instances = np.zeros((HEIGHT, WIDTH), np.uint8)
    for person in people:
        x0, y0, w, h = person["amodal_bbox"]
        instances[max(int(y0), 0):int(y0 + h), max(int(x0), 0):int(x0 + w)] = person["instance_id"]
    return instances


def _expected_heights(people: list[dict]) -> np.ndarray:
    """Per cell, the height of the nearest labelled person (what the region camera would say)."""
    rows, columns = np.indices((HEIGHT // STRIDE, WIDTH // STRIDE))
    centres = np.array([input_to_cells(p["center"], STRIDE) for p in people])
    nearest = np.argmin(np.hypot(columns[None] - centres[:, 0, None, None], rows[None] - centres[:, 1, None, None]),
                        axis=0)
    return np.array([p["amodal_bbox"][3] for p in people])[nearest]


def test_cell_geometry_round_trips_and_centres_cells_on_their_pixels() -> None:
    xy = np.array([[0.0, 0.0], [17.25, 3.5], [255.0, 191.0]])
    np.testing.assert_allclose(cells_to_input(input_to_cells(xy, STRIDE), STRIDE), xy)
    np.testing.assert_allclose(cells_to_input(np.array([0.0, 0.0]), STRIDE), [1.5, 1.5])  # pixels 0..3


def test_encoded_maps_have_unit_peaks_at_the_labels_and_the_mask_is_coverage() -> None:
    instances = _instances(PEOPLE)
    heatmaps = encode(PEOPLE, instances, CodecConfig(stride=STRIDE))
    assert heatmaps.shape == (HEATMAP_CHANNELS, HEIGHT // STRIDE, WIDTH // STRIDE)
    assert heatmaps.dtype == np.float32 and np.abs(heatmaps).max() <= 1.0
    assert heatmaps[:HANDEDNESS_CHANNELS.start].min() >= 0.0  # handedness alone is signed
    assert len(find_peaks(heatmaps[CENTRE_CHANNEL], 0.3)) == 3
    assert heatmaps[MASK_CHANNEL].mean() == pytest.approx((instances > 0).mean())


def test_people_drawn_together_are_each_drawn_as_alone_combined_by_maximum() -> None:
    # A fourth person standing in front of the first: their Gaussians overlap, and they share cells.
    people = [*PEOPLE, _person((75.2, 99.1), 90.0, 4)]
    instances = _instances(people)
    config = CodecConfig(stride=STRIDE, centre_offsets=True, fine_centre=True, head_map=True)
    together = encode(people, instances, config)
    alone = np.stack([encode([person], instances, config) for person in people])
    gaussian = [CENTRE_CHANNEL, *range(KEYPOINT_CHANNELS.start, KEYPOINT_CHANNELS.stop),
                *range(FINE_CENTRE_CHANNELS.start, FINE_CENTRE_CHANNELS.stop), HEAD_CHANNEL]
    assert np.array_equal(together[gaussian], alone[:, gaussian].max(axis=0))
    # Each person's share of a cell is the mean over its pixels, exactly, and the mask everyone's.
    cells = (HEIGHT // STRIDE, STRIDE, WIDTH // STRIDE, STRIDE)
    assert np.array_equal(together[MASK_CHANNEL], (instances > 0).reshape(cells).mean(axis=(1, 3), dtype=np.float32))
    shares = [(instances == person["instance_id"]).reshape(cells).mean(axis=(1, 3), dtype=np.float32)
              for person in people]
    handedness = np.zeros_like(together[HANDEDNESS_CHANNELS])
    for person, share in zip(people, shares, strict=True):
        handedness += share[None] * np.where(person["left_is_image_left"], 1.0, -1.0).astype(np.float32)[:, None, None]
    assert np.array_equal(together[HANDEDNESS_CHANNELS], handedness)


def test_pairs_are_stored_in_image_order_and_handedness_covers_the_person() -> None:
    facing, away = _person((60.3, 95.7), 100.0, 1), _person((180.2, 95.7), 100.0, 2, facing_away=True)
    instances = _instances([facing, away])
    heatmaps = encode([facing, away], instances, CodecConfig(stride=STRIDE))
    image_left_shoulder = heatmaps[KEYPOINT_CHANNELS.start + 5]
    for person in (facing, away):  # the image-left slot peaks at whichever shoulder is further left
        shoulders = np.asarray(person["keypoints"]).reshape(-1, 3)[5:7, :2]
        x, y = np.round(input_to_cells(shoulders[shoulders[:, 0].argmin()], STRIDE)).astype(int)
        assert image_left_shoulder[y, x] > 0.5
    cells = (HEIGHT // STRIDE, STRIDE, WIDTH // STRIDE, STRIDE)
    coverage = {i: (instances == i).reshape(cells).mean(axis=(1, 3)) for i in (1, 2)}
    # Facing the camera, the image-left member is the person's right one: -1; facing away +1; nobody's cells 0.
    np.testing.assert_allclose(heatmaps[HANDEDNESS_CHANNELS], np.broadcast_to(coverage[2] - coverage[1],
                                                                              heatmaps[HANDEDNESS_CHANNELS].shape))
    assert coverage[1].max() == coverage[2].max() == 1.0


def test_round_trip_recovers_people_keypoints_and_boxes() -> None:
    heatmaps = encode(PEOPLE, _instances(PEOPLE), CodecConfig(stride=STRIDE))
    decoded = decode(heatmaps, DecodeConfig(stride=STRIDE), expected_height_px=_expected_heights(PEOPLE))
    assert len(decoded) == 3
    for person in PEOPLE:
        match = min(decoded, key=lambda d: np.linalg.norm(d.centre - person["center"]))
        assert np.linalg.norm(match.centre - person["center"]) < 1.0
        truth = np.asarray(person["keypoints"]).reshape(-1, 3)
        errors = np.linalg.norm(match.keypoints[:, :2] - truth[:, :2], axis=1)
        assert errors.max() < STRIDE, errors  # the acceptance: within one output stride
        assert errors.mean() < 1.0
        assert (match.keypoints[:, 2] > 0.5).all()  # a peak between cells reads lower in either cell
        x0, y0, w, h = person["amodal_bbox"]
        assert match.box[1] == pytest.approx(y0, abs=1.0) and match.box[3] == pytest.approx(y0 + h, abs=1.0)
        assert match.box[0] <= truth[:, 0].min() and match.box[2] >= truth[:, 0].max()
        assert match.mask_cells.sum() > 0


def test_maps_of_the_retired_layout_and_of_no_layout_are_refused() -> None:
    with pytest.raises(ValueError, match="19 channels, the layout of networks from before the handedness maps"):
        decode(np.zeros((ANATOMICAL_CHANNELS, 8, 8), np.float32))
    with pytest.raises(ValueError, match="20 channels; a ScenePoseNet emits one of the layouts"):
        decode(np.zeros((ANATOMICAL_CHANNELS + 1, 8, 8), np.float32))


def _settled_case() -> tuple[np.ndarray, np.ndarray]:
    """Maps where each retired switch at its other value would decode other people: one person a little behind
    another with their ankles hidden (keypoint peaks shared out), people 1.2x as tall as the camera expects (height
    from head and ankles), a fine centre map (not read), a faded centre (a weak person), and noise."""
    behind, front = _person((100.0, 90.0), 100.0, 1), _person((112.0, 112.0), 100.0, 2)
    apart, faded = _person((200.0, 96.0), 100.0, 3, facing_away=True), _person((40.0, 100.0), 80.0, 4)
    people = [behind, front, apart, faded]
    heatmaps = encode(people, _instances(people), CodecConfig(stride=STRIDE, centre_offsets=True, fine_centre=True))
    for ankle in (15, 16):
        column, row = (int(round(v)) for v in input_to_cells(behind["keypoints"][3 * ankle:3 * ankle + 2], STRIDE))
        heatmaps[1 + 15:1 + 17, row - 2:row + 3, column - 2:column + 3] = 0.0
    column, row = (int(round(v)) for v in input_to_cells(faded["center"], STRIDE))
    heatmaps[CENTRE_CHANNEL, row - 3:row + 4, column - 3:column + 4] *= 0.2
    heatmaps += np.random.default_rng(7).uniform(-0.05, 0.05, heatmaps.shape).astype(np.float32)
    return heatmaps, np.full(heatmaps.shape[1:], 100.0 / 1.2)


def test_the_settled_decoding_finds_the_people_it_always_found() -> None:
    """What every bundle decodes (docs/decisions/0003-decoder-settings.md), pinned on maps where each retired switch
    at its other value would change the people: weak flag, score, box and per-person keypoint sums (x, y,
    confidence)."""
    heatmaps, heights = _settled_case()
    people = decode(heatmaps, DecodeConfig(stride=STRIDE), heights, weak_above=0.1)
    assert [person.weak for person in people] == [False, False, False, True]
    np.testing.assert_allclose([person.score for person in people], [1.0172, 0.9988, 0.9963, 0.1781], atol=1e-4)
    np.testing.assert_allclose([person.box for person in people],
                               [[81.0, 39.581, 118.0, 141.173], [181.0, 46.116, 218.0, 145.727],
                                [93.0, 62.276, 130.0, 161.607], [21.0, 60.047, 58.0, 139.73]], atol=1e-3)
    np.testing.assert_allclose([person.keypoints.sum(axis=0) for person in people],
                               [[1645.755, 1336.329, 13.616], [3400.307, 1444.486, 15.078],
                                [1903.819, 1716.266, 15.067], [680.131, 1549.583, 14.495]], atol=1e-3)


def test_the_upright_prior_is_a_parameter_whose_default_is_the_measured_one() -> None:
    """An experiment measures another prior by passing it, not by overwriting the module's constants."""
    from vc.deploy.decode import UPRIGHT_PRIOR, UprightPrior

    heatmaps, heights = _settled_case()
    config = DecodeConfig(stride=STRIDE)
    measured = decode(heatmaps, config, heights, prior=UprightPrior(UPRIGHT_OFFSETS.copy(), LOWER_ANKLE_OFFSET))
    default = decode(heatmaps, config, heights)
    np.testing.assert_array_equal([p.box for p in measured], [p.box for p in default])
    taller = UprightPrior(UPRIGHT_OFFSETS * 1.05, LOWER_ANKLE_OFFSET * 1.05)
    heights_under = [p.box[3] - p.box[1] for p in decode(heatmaps, config, heights, prior=taller)]
    assert max(heights_under) < max(p.box[3] - p.box[1] for p in default)  # keypoints spread wider: a shorter body
    assert UPRIGHT_PRIOR.offsets is UPRIGHT_OFFSETS  # one source for the measured prior


def test_a_stored_decode_config_naming_a_settled_switch_reads_as_without_it() -> None:
    stored = {**DecodeConfig(stride=STRIDE).__dict__, **SETTLED_SWITCHES}
    assert DecodeConfig(**stored_decode_fields(stored)) == DecodeConfig(stride=STRIDE)
    for name, settled in SETTLED_SWITCHES.items():
        with pytest.raises(RetiredSetting, match=f"{name}={str(not settled).lower()}, a decoding this version no "
                                                 f"longer has") as refused:
            stored_decode_fields({**stored, name: not settled})
        assert refused.value.field == name


def test_empty_and_flat_maps_decode_to_nobody() -> None:
    cells = (HEATMAP_CHANNELS, HEIGHT // STRIDE, WIDTH // STRIDE)
    assert decode(np.zeros(cells, np.float32)) == []
    assert encode([], np.zeros((HEIGHT, WIDTH), np.uint8)).max() == 0.0
    flat = np.full(cells, 0.9, np.float32)
    assert len(decode(flat)) == 1  # a plateau is one peak, not one per cell


def test_input_not_a_multiple_of_the_stride_is_refused() -> None:
    with pytest.raises(ValueError, match="multiple of the output stride"):
        encode([], np.zeros((HEIGHT + 2, WIDTH), np.uint8), CodecConfig(stride=STRIDE))


def test_stray_mask_and_keypoints_beyond_reach_do_not_stretch_the_box():
    person = _person((60.3, 95.7), 100.0, 1)
    instances = _instances([person])
    heatmaps = encode([person], instances, CodecConfig(stride=STRIDE))
    heights = np.full(heatmaps.shape[1:], 100.0)
    tidy = decode(heatmaps, DecodeConfig(stride=STRIDE), heights)[0].box
    heatmaps[MASK_CHANNEL, 20:30, 40:60] = 1.0  # a blob 100+ px to the right: nobody's, or someone undetected
    heatmaps[1 + 9, 24, 35] = 1.5  # a left wrist far out, stronger than the person's own (a neighbour's)
    stray = decode(heatmaps, DecodeConfig(stride=STRIDE), heights)[0]
    assert np.allclose(stray.box, tidy)
    assert not stray.mask_cells[:, 40:].any()
    assert tidy[2] - tidy[0] <= 0.6 * 100.0  # a pedestrian's box, not a crowd's


def test_the_box_may_take_its_height_from_the_person_s_head_and_ankles():
    """A person 1.2x as tall as the camera expects where their centre was found (an eye-level camera, a centre a
    few pixels off): the box spans their own head and feet; without confident ankles, and when the keypoints say
    more than ``keypoint_height_range`` off (a neighbour's ankle), the expected height."""
    person = _person((60.3, 95.7), 100.0, 1)
    heatmaps = encode([person], _instances([person]), CodecConfig(stride=STRIDE))
    expected = np.full(heatmaps.shape[1:], 100.0 / 1.2)
    x0, y0, w, h = person["amodal_bbox"]
    own = decode(heatmaps, DecodeConfig(stride=STRIDE), expected)[0].box
    assert own[1] == pytest.approx(y0, abs=1.0) and own[3] == pytest.approx(y0 + h, abs=1.0)
    without_ankles = heatmaps.copy()
    without_ankles[1 + 15:1 + 17] = 0.0
    centred = decode(without_ankles, DecodeConfig(stride=STRIDE), expected)[0].box
    assert centred[3] - centred[1] == pytest.approx(100.0 / 1.2)
    too_far = np.full(heatmaps.shape[1:], 100.0 / 1.6)
    fallen_back = decode(heatmaps, DecodeConfig(stride=STRIDE), too_far)[0].box
    assert fallen_back[3] - fallen_back[1] == pytest.approx(100.0 / 1.6)


def test_a_blurred_double_peak_is_one_person_but_neighbours_stay_two():
    heights = np.full((HEIGHT // STRIDE, WIDTH // STRIDE), 100.0)

    def people_found(separation_cells: float) -> int:
        heatmaps = np.zeros((HEATMAP_CHANNELS, *heights.shape), np.float32)
        for offset, peak in ((0.0, 1.0), (separation_cells, 0.8)):
            columns = np.arange(heights.shape[1]) - (20 + offset)
            rows = np.arange(heights.shape[0]) - 24
            blob = peak * np.exp(-(rows[:, None] ** 2 + columns[None] ** 2) / (2 * 0.6**2))
            heatmaps[CENTRE_CHANNEL] = np.maximum(heatmaps[CENTRE_CHANNEL], blob)
        return len(decode(heatmaps, DecodeConfig(stride=STRIDE), heights))

    assert people_found(2.0) == 1  # 8 px apart: 0.08 of a 100 px person
    assert people_found(8.0) == 2  # 32 px apart: two people side by side


def test_noise_decodes_to_at_most_max_people_strongest_first() -> None:
    noise = np.random.default_rng(0).random((HEATMAP_CHANNELS, 80, 300)).astype(np.float32)
    config = DecodeConfig(stride=STRIDE, max_people=25)
    people = decode(noise, config)
    strongest = [value for value, _ in find_peaks(noise[CENTRE_CHANNEL], config.centre_threshold)]
    assert 0 < len(people) <= 25 < len(strongest)
    assert people[0].score == pytest.approx(strongest[0])
    assert np.all(np.diff([person.score for person in people]) <= 0)



def test_people_searched_together_get_the_keypoints_each_would_get_alone() -> None:
    """The keypoint search runs over all people at once in windows of the largest person's size: small and large
    people, people at every edge of the map, and a plateau (ties go to the first cell in reading order)."""
    rng = np.random.default_rng(4)
    maps = rng.random((17, 48, 80)).astype(np.float32)
    maps[:, 10:30, 20:40] = 0.9  # a plateau wider than a small person's window
    centres = np.array([[0.0, 0.0], [79.0, 47.0], [30.2, 20.7], [5.5, 44.1], [78.4, 2.2], [40.0, 24.0], [25.0, 15.0]])
    heights = np.array([4.0, 30.0, 12.5, 8.0, 60.0, 2.0, 6.0])
    config = DecodeConfig(stride=STRIDE)
    together = _keypoints(maps, centres, heights, config)
    alone = np.concatenate([_keypoints(maps, centres[k:k + 1], heights[k:k + 1], config) for k in range(len(centres))])
    np.testing.assert_array_equal(together, alone)
    assert (together[..., 2] > 0).sum() > 0.8 * together[..., 2].size  # most keypoints were searched and found


def test_a_keypoint_peak_goes_to_one_person_and_keeps_a_neighbour_s_feet_out_of_a_person_s_box():
    """One person a little behind another, their feet hidden by the one in front, whose feet are strong. The front
    person keeps their own ankles; the person behind gets none of theirs, and their box falls back to the height the
    camera expects instead of reaching down to the front person's feet."""
    behind, front = _person((100.0, 90.0), 100.0, 1), _person((112.0, 112.0), 100.0, 2)
    heatmaps = encode([behind, front], _instances([behind, front]), CodecConfig(stride=STRIDE))
    heights = np.full(heatmaps.shape[1:], 100.0)
    for ankle in (15, 16):
        column, row = (int(round(v)) for v in input_to_cells(behind["keypoints"][3 * ankle:3 * ankle + 2], STRIDE))
        heatmaps[1 + 15:1 + 17, row - 2:row + 3, column - 2:column + 3] = 0.0  # the ankle maps only
    found = decode(heatmaps, DecodeConfig(stride=STRIDE), heights)
    assert len(found) == 2
    behind_found, front_found = sorted(found, key=lambda person: person.centre[1])
    assert behind_found.box[3] == pytest.approx(behind["amodal_bbox"][1] + 100.0, abs=1.0)  # its own height
    assert behind_found.keypoints[[15, 16], 2].max() < 0.2  # no ankles of its own
    for person, truth in ((front_found, front), (behind_found, behind)):
        own = np.arange(17) if person is front_found else np.arange(15)  # everything but the hidden ankles
        errors = np.linalg.norm(person.keypoints[own, :2] - np.reshape(truth["keypoints"], (-1, 3))[own, :2], axis=1)
        assert errors.max() < STRIDE
    assert front_found.box[3] == pytest.approx(front["amodal_bbox"][1] + 100.0, abs=1.0)


def test_a_sharper_centre_map_keeps_one_person_behind_another_as_two():
    # Eye level: the farther person (0.85 of the height) stands behind and 0.1 heights beside the nearer one, as
    # the people TUD-Stadtmitte's bundles missed do (benchmarks/results/centre_sigma_tud.md).
    front = _person((128.0, 96.0), 120.0, 1)
    behind = _person((128.0 + 12.0, 96.0 - 6.0), 102.0, 2)
    people = [front, behind]
    heights = _expected_heights(people)

    def people_found(settings: dict) -> int:
        heatmaps = encode(people, _instances(people), replace(settings["codec"], stride=STRIDE))
        return len(decode(heatmaps, replace(settings["decode"], stride=STRIDE), heights))

    default = {"codec": CodecConfig(), "decode": DecodeConfig()}
    assert people_found(default) == 1  # the two Gaussians merge into one peak
    sharp = centre_map_settings(0.04)
    assert people_found(sharp) == 2
    assert sharp["loss"].detection == pytest.approx(4.0)  # a quarter of the area, four times the weight


def test_weak_people_are_decoded_when_asked_and_take_nothing_from_the_others():
    """Two people side by side, the right one's centre peak faded below the threshold: asked for weak people, the
    decoder also returns the faded one, flagged weak, and the other comes out exactly as without it (its mask
    cells and keypoint peaks are not shared out with the weak one)."""
    left, right = _person((100.0, 96.0), 100.0, 1), _person((128.0, 96.0), 100.0, 2)
    heatmaps = encode([left, right], _instances([left, right]), CodecConfig(stride=STRIDE))
    column, row = (int(round(v)) for v in input_to_cells(right["center"], STRIDE))
    heatmaps[CENTRE_CHANNEL, row - 3:row + 4, column - 3:column + 4] *= 0.2
    heights = np.full(heatmaps.shape[1:], 100.0)
    config = DecodeConfig(stride=STRIDE)
    alone = decode(heatmaps, config, heights)
    with_weak = decode(heatmaps, config, heights, weak_above=0.1)
    assert len(alone) == 1 and not alone[0].weak
    assert [person.weak for person in with_weak] == [False, True]
    strong, weak = with_weak
    np.testing.assert_array_equal(strong.mask_cells, alone[0].mask_cells)
    np.testing.assert_allclose(strong.box, alone[0].box)
    np.testing.assert_allclose(strong.keypoints, alone[0].keypoints)
    assert weak.score < config.centre_threshold and abs(weak.centre[0] - right["center"][0]) < 2.0
    (above,) = decode(heatmaps, config, heights, weak_above=0.5)  # above the threshold: nobody weak
    assert not above.weak and np.allclose(above.box, alone[0].box)


def test_centre_offsets_point_every_person_pixel_to_its_own_centre() -> None:
    instances = _instances(PEOPLE)
    heatmaps = encode(PEOPLE, instances, CodecConfig(stride=STRIDE, centre_offsets=True))
    assert heatmaps.shape[0] == OFFSET_CHANNELS
    np.testing.assert_array_equal(heatmaps[:HEATMAP_CHANNELS], encode(PEOPLE, instances, CodecConfig(stride=STRIDE)))
    offsets = heatmaps[CENTRE_OFFSET_CHANNELS]
    cells = (HEIGHT // STRIDE, STRIDE, WIDTH // STRIDE, STRIDE)
    for person in PEOPLE:
        owned = (instances == person["instance_id"]).reshape(cells).mean(axis=(1, 3)) > 0.5
        rows, columns = np.nonzero(owned)
        height_cells = person["amodal_bbox"][3] / STRIDE
        voted = np.column_stack([columns, rows]) + offsets[:, rows, columns].T * height_cells
        np.testing.assert_allclose(voted, np.broadcast_to(input_to_cells(person["center"], STRIDE), voted.shape),
                                   atol=1e-4)
    assert not offsets[:, heatmaps[MASK_CHANNEL] == 0].any()  # nothing to learn off people


def _one_blob_for_two(centre_offsets: bool) -> tuple[list[dict], np.ndarray, np.ndarray]:
    """Two people side by side, their bodies touching, whose centre map a network blurred into one peak between
    them: the codec's maps with the centre channel replaced by a single wide Gaussian."""
    people = [_person((110.3, 95.7), 100.0, 1), _person((146.3, 95.7), 100.0, 2)]
    heatmaps = encode(people, _instances(people), CodecConfig(stride=STRIDE, centre_offsets=centre_offsets))
    rows, columns = np.indices(heatmaps.shape[1:])
    between = input_to_cells([128.3, 95.7], STRIDE)
    heatmaps[CENTRE_CHANNEL] = np.exp(-((columns - between[0]) ** 2 / 40.0 + (rows - between[1]) ** 2 / 8.0))
    return people, heatmaps, np.full(heatmaps.shape[1:], 100.0)


def test_votes_split_one_blob_into_its_two_people_each_boxed_by_its_own_pixels() -> None:
    people, merged, heights = _one_blob_for_two(centre_offsets=False)
    assert len(decode(merged, DecodeConfig(stride=STRIDE), heights)) == 1  # the centre map alone: one person
    people, heatmaps, heights = _one_blob_for_two(centre_offsets=True)
    decoded = decode(heatmaps, DecodeConfig(stride=STRIDE), heights)
    assert len(decoded) == 2
    for person in people:
        match = min(decoded, key=lambda d: np.linalg.norm(d.centre - person["center"]))
        x0, _, width, _ = person["amodal_bbox"]
        assert np.linalg.norm(match.centre - person["center"]) < STRIDE
        # the box spans this person's pixels, not the pair's
        assert match.box[0] == pytest.approx(x0, abs=STRIDE + 3.0) and match.box[2] == pytest.approx(
            x0 + width, abs=STRIDE + 3.0)


def test_a_shorter_vote_reach_keeps_the_votes_of_a_person_close_to_another_apart() -> None:
    """Two people 0.12 heights apart, the second covering most of the first, the centre map one peak on the first
    (what a network draws at 48 px): the pixels of the second vote for their own centre, inside the default vote
    reach (the centre separation, 0.15) of that peak, which claims them. A shorter reach (``vote_separation``)
    leaves them free, and they are the second person."""
    front, behind = _person((110.3, 95.7), 100.0, 1), _person((122.3, 95.7), 100.0, 2)
    heatmaps = encode([front, behind], _instances([front, behind]), CodecConfig(stride=STRIDE, centre_offsets=True))
    rows, columns = np.indices(heatmaps.shape[1:])
    x, y = input_to_cells(front["center"], STRIDE)
    heatmaps[CENTRE_CHANNEL] = np.exp(-((columns - x) ** 2 + (rows - y) ** 2) / (2 * 3.0**2))
    heights = np.full(heatmaps.shape[1:], 100.0)
    assert len(decode(heatmaps, DecodeConfig(stride=STRIDE), heights)) == 1
    found = decode(heatmaps, DecodeConfig(stride=STRIDE, vote_separation=0.08), heights)
    assert len(found) == 2
    np.testing.assert_allclose(sorted(person.centre[0] for person in found), [110.3, 122.3], atol=1.5)


def test_the_fine_centre_map_holds_each_centre_at_twice_the_resolution() -> None:
    people = [_person((110.3, 95.7), 48.0, 1), _person((171.0, 60.2), 80.0, 2)]
    heatmaps = encode(people, _instances(people), CodecConfig(stride=STRIDE, centre_offsets=True, fine_centre=True))
    assert heatmaps.shape == (FINE_CHANNELS, HEIGHT // STRIDE, WIDTH // STRIDE)
    coarse_only = encode(people, _instances(people), CodecConfig(stride=STRIDE, centre_offsets=True))
    np.testing.assert_array_equal(heatmaps[:OFFSET_CHANNELS], coarse_only)  # the other maps as before
    fine = fine_centre_map(heatmaps[FINE_CENTRE_CHANNELS])
    assert fine.shape == (2 * HEIGHT // STRIDE, 2 * WIDTH // STRIDE)
    np.testing.assert_array_equal(fine_centre_channels(fine), heatmaps[FINE_CENTRE_CHANNELS])
    peaks = find_peaks(fine, 0.3)
    assert len(peaks) == 2
    for person in people:  # each peak where the person's centre is, in fine cells (half a cell's pixels)
        expected = cells_to_fine(input_to_cells(person["center"], STRIDE))
        assert min(np.linalg.norm(position - expected) for _, position in peaks) < 0.25


def test_the_decoder_reads_the_coarse_centre_map_and_not_the_fine_one() -> None:
    """Two 48 px people 0.125 heights (1.5 cells) apart: the coarse centre map as a network draws it there, one
    blurred peak between them; the fine map two. The fine map trains the network and is not read
    (docs/decisions/0010-fine-centre-map.md): the same person as from the maps without it."""
    front, behind = _person((110.3, 95.7), 48.0, 1), _person((116.3, 95.7), 48.0, 2)
    heatmaps = encode([front, behind], _instances([front, behind]),
                      CodecConfig(stride=STRIDE, centre_offsets=True, fine_centre=True))
    rows, columns = np.indices(heatmaps.shape[1:])
    x, y = input_to_cells([113.3, 95.7], STRIDE)
    heatmaps[CENTRE_CHANNEL] = np.exp(-((columns - x) ** 2 + (rows - y) ** 2) / (2 * 1.5**2))
    heights = np.full(heatmaps.shape[1:], 48.0)
    assert len(find_peaks(fine_centre_map(heatmaps[FINE_CENTRE_CHANNELS]), 0.3)) == 2
    config = DecodeConfig(stride=STRIDE, min_centre_separation=0.1, vote_separation=0.1)
    (with_fine,) = decode(heatmaps, config, heights)
    (without_fine,) = decode(heatmaps[:OFFSET_CHANNELS], config, heights)
    assert with_fine.box.tolist() == without_fine.box.tolist()
    assert with_fine.keypoints.tolist() == without_fine.keypoints.tolist()


def test_a_lone_person_s_votes_add_nobody_and_scattered_votes_are_not_a_person() -> None:
    person = _person((110.3, 95.7), 100.0, 1)
    heatmaps = encode([person], _instances([person]), CodecConfig(stride=STRIDE, centre_offsets=True))
    heights = np.full(heatmaps.shape[1:], 100.0)
    assert len(decode(heatmaps, DecodeConfig(stride=STRIDE), heights)) == 1
    # votes sprayed everywhere (offsets of noise): no cluster holds a third of a person
    heatmaps[CENTRE_OFFSET_CHANNELS] = np.random.default_rng(0).uniform(-0.6, 0.6, heatmaps[CENTRE_OFFSET_CHANNELS]
                                                                        .shape)
    assert len(decode(heatmaps, DecodeConfig(stride=STRIDE), heights)) == 1


@pytest.mark.parametrize("row, column", [(0, 0), (17, 30), (39, 63), (5, 62)])
def test_window_sums_brought_up_to_date_around_emptied_cells_equal_summing_again(row, column) -> None:
    # The vote step empties one window a round and sums again only around it (step 1b): at the borders too.
    rng = np.random.default_rng(row * 100 + column)
    grid = rng.uniform(0.0, 1.0, (40, 64)) * (rng.uniform(size=(40, 64)) < 0.3)
    radius = 3
    sums = _window_sums(grid, radius)
    grid[max(0, row - radius):row + radius + 1, max(0, column - radius):column + radius + 1] = 0.0
    _update_window_sums(sums, grid, radius, row, column)
    np.testing.assert_allclose(sums, _window_sums(grid, radius), atol=1e-12)
    assert sums[row, column] == pytest.approx(0.0, abs=1e-12)


def _peaks_by_definition(maps: np.ndarray, threshold: float) -> set[tuple[int, int, int]]:
    """(map, row, column) of every cell above ``threshold``, at least as high as its 8 neighbours and strictly
    higher than the 4 before it in reading order: local_maxima's rule, one cell at a time."""
    channels, height, width = maps.shape
    peaks = set()
    for channel, row, column in np.ndindex(channels, height, width):
        value = maps[channel, row, column]
        neighbours = [(dy, dx) for dy in (-1, 0, 1) for dx in (-1, 0, 1) if (dy, dx) != (0, 0)
                      and 0 <= row + dy < height and 0 <= column + dx < width]
        before = [(dy, dx) for dy, dx in neighbours if (dy, dx) < (0, 0)]
        if value > threshold and all(value >= maps[channel, row + dy, column + dx] for dy, dx in neighbours) and all(
                value > maps[channel, row + dy, column + dx] for dy, dx in before):
            peaks.add((channel, row, column))
    return peaks


@pytest.mark.parametrize("windows", [None, [(0, 12, 0, 7), (0, 12, 7, 20)], [(3, 9, 2, 5), (0, 4, 11, 20)]])
def test_local_maxima_are_the_peaks_by_definition_in_the_whole_map_or_in_windows(windows) -> None:
    # Coarse values (as int8 networks give) make ties, plateaus included; windows meet the map's borders and each
    # other, and their peaks are judged against neighbours outside them.
    maps = np.round(np.random.default_rng(3).uniform(0.0, 1.0, (3, 12, 20)) * 6) / 6
    maps[1, 4:7, 8:11] = 1.0  # a plateau: its first cell in reading order only
    found, values, positions = local_maxima(maps, 0.2, windows=windows)
    expected = {(c, r, x) for c, r, x in _peaks_by_definition(maps, 0.2)
                if windows is None or any(top <= r < bottom and left <= x < right
                                          for top, bottom, left, right in windows)}
    assert len(found) == len(expected)
    for channel, row, column in expected:  # a refined position stays within half a cell of its peak's cell
        assert np.any((found == channel) & (np.abs(positions - [column, row]) <= 0.5).all(axis=1))
        assert values[(found == channel) & (np.abs(positions - [column, row]) <= 0.5).all(axis=1)][0] == maps[
            channel, row, column]
    if windows is None:
        assert (1, 4, 8) in expected and (1, 4, 9) not in expected
    for channel in range(3):  # strongest first within each map
        assert np.all(np.diff(values[found == channel]) <= 0)
    assert len(local_maxima(maps, 0.2, windows=[])[0]) == 0


def test_pairs_are_exchanged_where_flagged_and_nowhere_else() -> None:
    keypoints = np.arange(17 * 3, dtype=float).reshape(17, 3)
    flags = np.array([True, False, False, True, False, False, False, True])  # eyes, elbows, ankles
    swapped = swap_pairs(keypoints, flags)
    for (left, right), flag in zip(PAIRS, flags, strict=True):
        assert np.array_equal(swapped[[left, right]], keypoints[[right, left]] if flag else keypoints[[left, right]])
    assert np.array_equal(swapped[0], keypoints[0])  # the nose has no pair
    assert np.array_equal(swap_pairs(swapped, flags), keypoints)
    assert not np.shares_memory(swap_pairs(keypoints, np.zeros(8, bool)), keypoints)


@pytest.mark.parametrize("count", [1, 2, 7, 10])
def test_the_vote_step_s_median_is_numpy_s(count) -> None:
    values = np.random.default_rng(count).uniform(20.0, 90.0, count)
    assert _median(values) == np.median(values)


def test_several_peoples_pairs_are_exchanged_each_by_their_own_flags() -> None:
    rng = np.random.default_rng(3)
    keypoints = rng.normal(size=(4, 17, 3))
    flags = rng.random((4, 8)) < 0.5
    together = swap_pairs(keypoints, flags)
    for person in range(4):
        assert np.array_equal(together[person], swap_pairs(keypoints[person], flags[person]))
