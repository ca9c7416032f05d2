"""The head and size maps (issue 57 item 2, docs/decisions/0058-a-head-map-in-every-region.md): what the codec
draws, how the loss weighs them, and the decoder's step 5 — people whose centres blur into one peak read again from
their heads, added where no kept person holds them, one head one person."""

from __future__ import annotations

from dataclasses import replace
from types import SimpleNamespace

import numpy as np
import pytest
import torch
from test_codec import STRIDE, _instances, _person

from vc.deploy.decode import (
    HEAD_HEIGHT_AGREEMENT,
    HEAD_UNION_IOU,
    SAME_HEAD_REACH,
    DecodeConfig,
    decode,
    decode_readings,
    one_head_each,
    with_heads_added,
)
from vc.deploy.heatmaps import (
    CENTRE_CHANNEL,
    FINE_CHANNELS,
    HEAD_CHANNEL,
    HEAD_CHANNELS,
    MASK_CHANNEL,
    SIZE_CHANNEL,
    SIZE_UNIT_CELLS,
    channel_names,
    input_to_cells,
)
from vc.errors import InputError
from vc.model.codec import CodecConfig, encode, head_point
from vc.model.loss import LossWeights, heatmap_terms, scene_pose_loss
from vc.stages.config import train_settings

HEAD_CODEC = CodecConfig(stride=STRIDE, centre_offsets=True, fine_centre=True, head_map=True)


def test_the_head_map_peaks_at_each_head_and_the_size_map_holds_each_person_s_log_height():
    people = [_person((60.3, 95.7), 100.0, 1), _person((171.0, 80.2), 60.0, 2)]
    instances = _instances(people)
    heatmaps = encode(people, instances, HEAD_CODEC)
    assert heatmaps.shape[0] == HEAD_CHANNELS and channel_names(HEAD_CHANNELS)[-2:] == ("head", "log_height_20_cells")
    np.testing.assert_array_equal(heatmaps[:FINE_CHANNELS], encode(people, instances, replace(HEAD_CODEC,
                                                                                              head_map=False)))
    for person in people:
        head = head_point(person)
        assert head[1] < person["center"][1] - 0.35 * person["amodal_bbox"][3]  # the face, above the shoulders
        column, row = np.round(input_to_cells(head, STRIDE)).astype(int)
        around = heatmaps[HEAD_CHANNEL, row - 2:row + 3, column - 2:column + 3]
        assert heatmaps[HEAD_CHANNEL, row, column] == around.max() > 0.75
        column, row = np.round(input_to_cells(person["center"], STRIDE)).astype(int)
        assert heatmaps[SIZE_CHANNEL, row, column] == pytest.approx(
            np.log(person["amodal_bbox"][3] / STRIDE / SIZE_UNIT_CELLS))
    assert (heatmaps[SIZE_CHANNEL][heatmaps[MASK_CHANNEL] == 0] == 0).all()  # nobody's cells: nothing to learn


def test_the_head_map_comes_after_the_fine_centre_map_and_a_training_without_it_is_refused_by_field():
    with pytest.raises(ValueError, match="fine_centre"):
        CodecConfig(centre_offsets=True, head_map=True)
    assert train_settings(centre_offsets=True, fine_centre=True, head_map=True).train_config().codec.head_map
    with pytest.raises(InputError, match="train.head_map"):
        train_settings(centre_offsets=True, head_map=True)


def test_the_head_map_is_weighed_as_the_centre_map_and_the_size_map_as_the_offsets_on_people_only():
    prediction, targets = torch.rand(2, HEAD_CHANNELS, 8, 8), torch.rand(2, HEAD_CHANNELS, 8, 8)
    targets[:, MASK_CHANNEL, :4] = 0.0
    terms = heatmap_terms(prediction, targets)
    assert float(terms["head"]) == pytest.approx(
        float((prediction[:, HEAD_CHANNEL] - targets[:, HEAD_CHANNEL]).square().mean()))
    moved = prediction.clone()
    moved[:, SIZE_CHANNEL, :4] += 5.0  # where nobody is, the size is not learned
    assert float(heatmap_terms(moved, targets)["size"]) == pytest.approx(float(terms["size"]))
    for weight, term in (("detection", "head"), ("centre_offsets", "size")):
        loss, _ = scene_pose_loss({"beliefs": [], "heatmaps": prediction}, targets, LossWeights())
        heavier, _ = scene_pose_loss({"beliefs": [], "heatmaps": prediction}, targets,
                                     replace(LossWeights(), **{weight: getattr(LossWeights(), weight) + 1.0}))
        others = {"detection": ("detection", "fine_centre"), "centre_offsets": ("centre_offsets",)}[weight]
        assert float(heavier - loss) == pytest.approx(float(terms[term]) + sum(float(terms[o]) for o in others),
                                                      rel=1e-5)


def _blurred_pair(gap: float) -> tuple[list[dict], np.ndarray]:
    """Two 100 px people ``gap`` px apart whose centre map holds one peak, on the first, as a network draws two
    people one beside another that it cannot tell apart; their heads apart in the head map."""
    people = [_person((110.3, 95.7), 100.0, 1), _person((110.3 + gap, 95.7), 100.0, 2)]
    heatmaps = encode(people, _instances(people), HEAD_CODEC)
    rows, columns = np.indices(heatmaps.shape[1:])
    x, y = input_to_cells(people[0]["center"], STRIDE)
    heatmaps[CENTRE_CHANNEL] = np.exp(-((columns - x) ** 2 + (rows - y) ** 2) / (2 * 3.0**2))
    return people, heatmaps


#: Step 1b's votes add nobody: the first reading is the centre map's peaks alone.
NO_VOTES = DecodeConfig(stride=STRIDE, vote_support=10.0)


def test_people_whose_centres_make_one_peak_are_found_again_from_their_heads():
    people, heatmaps = _blurred_pair(gap=24.0)
    heights = np.full(heatmaps.shape[1:], 100.0)
    assert len(decode(heatmaps[:FINE_CHANNELS], NO_VOTES, heights)) == 1  # without the head map: one of them
    found = decode(heatmaps, NO_VOTES, heights)
    assert [person.head_found for person in found] == [False, True]
    added = found[1]
    assert added.centre == pytest.approx(people[1]["center"], abs=1.5)  # the head, moved by offset x size
    x0, y0, width, height = people[1]["amodal_bbox"]
    assert added.box[1] == pytest.approx(y0, abs=2.0) and added.box[3] == pytest.approx(y0 + height, abs=2.0)
    assert added.mask_cells.any()


@pytest.mark.parametrize("size_factor", [1.05, 1 / 1.05, 1.3, 1 / 1.3])
def test_a_person_read_from_the_heads_is_as_tall_as_their_keypoints_where_the_size_map_agrees(size_factor):
    people, heatmaps = _blurred_pair(gap=24.0)
    heatmaps[SIZE_CHANNEL] += np.log(size_factor)  # the size map reads them this much taller than they are
    added = decode(heatmaps, NO_VOTES, np.full(heatmaps.shape[1:], 100.0))[1]
    assert added.head_found
    _, y0, _, height = people[1]["amodal_bbox"]
    if 1 / HEAD_HEIGHT_AGREEMENT <= size_factor <= HEAD_HEIGHT_AGREEMENT:  # their head and ankles place the box
        assert added.box[1] == pytest.approx(y0, abs=2.0) and added.box[3] == pytest.approx(y0 + height, abs=2.0)
    else:  # the size map's height, centred on the centre it placed
        assert added.box[3] - added.box[1] == pytest.approx(size_factor * height, abs=1.0)
        assert (added.box[1] + added.box[3]) / 2 == pytest.approx(added.centre[1])


def test_a_person_read_from_the_heads_whose_box_a_kept_person_holds_is_not_added():
    _, heatmaps = _blurred_pair(gap=8.0)  # the two boxes overlap beyond HEAD_UNION_IOU
    heights = np.full(heatmaps.shape[1:], 100.0)
    readings = decode_readings(heatmaps, NO_VOTES, heights)
    assert sum(person.head_found for person in readings) == 2  # both heads read
    assert [person.head_found for person in decode(heatmaps, NO_VOTES, heights)] == [False]
    # a caller that does not keep the first reading's person (a region: feet in a neighbour's area) adds them
    assert len(with_heads_added([person for person in readings if person.head_found], 100)) == 2


def _someone(box: list[float], head_found: bool = False, weak: bool = False) -> SimpleNamespace:
    return SimpleNamespace(box=np.array(box, float), head_found=head_found, weak=weak)


def _ids(people: list) -> list[int]:
    return [id(person) for person in people]


def test_the_union_adds_people_from_the_heads_below_the_overlap_and_at_most_max_people():
    kept = _someone([0, 0, 40, 100])
    beside = _someone([30, 0, 70, 100], head_found=True)  # IoU 10 / 70
    over = _someone([10, 0, 50, 100], head_found=True)  # IoU 30 / 50
    assert 10 / 70 < HEAD_UNION_IOU < 30 / 50
    assert _ids(with_heads_added([kept, beside, over], 100)) == _ids([kept, beside])
    assert _ids(with_heads_added([kept, beside, over], 1)) == _ids([kept])
    weak = _someone([0, 0, 40, 100], weak=True)  # a tracker's weak person holds nobody's place
    assert _ids(with_heads_added([weak, over], 100)) == _ids([weak, over])


def test_one_head_one_person():
    person = _someone([0, 0, 40, 100])
    near = SAME_HEAD_REACH * 100 - 0.5  # within a tenth of the person's height of their head (20, 0)
    again = _someone([near, 0, near + 40, 60], head_found=True)  # another box, the same head
    apart = _someone([near + 40, 0, near + 80, 60], head_found=True)
    assert _ids(one_head_each([person, again, apart])) == _ids([person, apart])
    first_again = _someone([near, 0, near + 40, 60])  # two heads of the first reading are the decoder's to part
    assert _ids(one_head_each([person, first_again])) == _ids([person, first_again])
    weak = _someone([0, 0, 40, 100], weak=True)  # a tracker's weak person is nobody's head
    assert _ids(one_head_each([weak, again])) == _ids([weak, again])
