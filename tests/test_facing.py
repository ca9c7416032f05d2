"""The facing model: which way a person faces, read from their crop (vc.model.facing, vc.deploy.facing)."""

from __future__ import annotations

import json
import shutil

import numpy as np
import onnxruntime as ort
import pytest
import torch
from crop_factory import pasted

from vc.deploy.bundle import FACING, MANIFEST, load_bundle
from vc.deploy.facing import (
    CLASSIFIER_WEIGHT_BELOW,
    CROP_MARGIN,
    CROP_SIZE,
    FACE_AHEAD_OF_EARS,
    FRAME_INPUT,
    HEAD_OUTPUT,
    HEAD_READ_BELOW_PX,
    MIRRORED_FROM_PX,
    ROIS_INPUT,
    FacingReader,
    crop_rois,
    face_ahead,
    front_logits,
    mirrored,
    ordered_by_facing,
)
from vc.deploy.heatmaps import PAIRS
from vc.deploy.runtime import Person, Runtime
from vc.errors import InputError
from vc.model.export import export_facing, with_facing
from vc.model.facing import (
    FACING_MODEL,
    FACING_REPORT,
    HEAD_ROWS,
    MEMBER_SEED_STRIDE,
    FacingCrops,
    FacingNet,
    TurnCrops,
    camera_look,
    crop_graph,
    face_across,
    moved,
    seen_from_front,
    train_distilled_facing,
    train_face_turn,
    train_facing,
    train_head_colours,
)
from vc.stages.train import train_facing_model


def _crops(count: int, seed: int) -> FacingCrops:
    """People whose front shows a light face at the top of the crop and whose back shows dark hair there, in clothes
    of any colour: a pattern a classifier learns in a few steps."""
    rng = np.random.default_rng(seed)
    crops = rng.integers(0, 60, (count, CROP_SIZE[1], CROP_SIZE[0], 3)).astype(np.uint8)
    crops[:, 14:, 8:24] = rng.integers(30, 220, (count, 1, 1, 3))
    front = rng.random(count) < 0.5
    crops[front, 3:12, 11:21] = (225, 185, 150)
    crops[~front, 3:12, 11:21] = (25, 20, 15)
    return FacingCrops(crops, front)


def _turn_crops(count: int, seed: int) -> TurnCrops:
    """People whose face, a light patch at the top of the crop, shows on the side it points to (in profile) or in
    the middle (along the view): a pattern a network learns in a few steps."""
    rng = np.random.default_rng(seed)
    crops = rng.integers(0, 60, (count, CROP_SIZE[1], CROP_SIZE[0], 3)).astype(np.uint8)
    crops[:, 3:12, 10:22] = (25, 20, 15)  # hair
    across = rng.choice([-1.0, 0.0, 1.0], count).astype(np.float32)
    for crop, points in zip(crops, across, strict=True):
        left = 14 + int(points) * 5
        crop[4:11, left:left + 4] = (225, 185, 150)
    return TurnCrops(crops, across)


@pytest.fixture(scope="module")
def trained():
    torch.set_num_threads(1)
    return train_facing(_crops(1024, 0), _crops(128, 1), seed=3, epochs=4, show_progress=False)


@pytest.fixture(scope="module")
def turned():
    torch.set_num_threads(1)
    return train_face_turn(_turn_crops(1024, 0), _turn_crops(128, 1), seed=3, epochs=4, show_progress=False)


@pytest.fixture(scope="module")
def headed():
    torch.set_num_threads(1)
    return train_head_colours(_crops(1024, 0), _crops(128, 1), seed=3)


def _head_logits(head, crops: np.ndarray) -> np.ndarray:
    with torch.no_grad():
        return head.net(torch.from_numpy(np.ascontiguousarray(crops)).permute(0, 3, 1, 2).float() / 255.0).numpy()


def test_the_crop_is_the_box_a_little_taller_and_twice_as_tall_as_wide():
    rois = crop_rois(np.array([[10.0, 20.0, 30.0, 119.0]]))[0]
    height, width = rois[3] - rois[1], rois[2] - rois[0]
    assert height == pytest.approx(99.0 * CROP_MARGIN)
    assert height / width == pytest.approx(CROP_SIZE[1] / CROP_SIZE[0])
    assert (rois[0] + rois[2]) / 2 == pytest.approx(20.5)  # the box's centre, in pixel edges
    assert (rois[1] + rois[3]) / 2 == pytest.approx(70.0)


def test_the_crop_graph_cuts_each_person_out_of_the_frame_as_it_is():
    frame = np.zeros((120, 160, 3), np.uint8)
    frame[20:100, 40:80] = (200, 0, 0)  # left half of the crop red, right half blue
    frame[20:100, 80:120] = (0, 0, 200)
    session = ort.InferenceSession(crop_graph().SerializeToString(), providers=["CPUExecutionProvider"])
    rois = np.array([[40.0, 20.0, 120.0, 180.0], [0.0, 0.0, 16.0, 32.0]], np.float32)
    crops = session.run(None, {FRAME_INPUT: frame[None], ROIS_INPUT: rois})[0]
    assert crops.shape == (2, 3, CROP_SIZE[1], CROP_SIZE[0])
    left, right = crops[0, :, 2:28, 2:14], crops[0, :, 2:28, 18:30]  # rows of 2.5 px: the people end at row 32
    assert left[0].mean() == pytest.approx(200 / 255, abs=0.02) and left[2].max() < 0.02
    assert right[2].mean() == pytest.approx(200 / 255, abs=0.02) and right[0].max() < 0.02
    assert crops[1].max() == 0.0  # black where nobody stands


@pytest.mark.parametrize(("image_left", "offset", "expected"), [
    ([False] * 8, 10.0, True),  # left shoulder and hip on the image's right: the front
    ([True] * 8, -10.0, False),
    ([True, False] * 4, 10.0, None),  # shoulders and hips disagree: turning, no front to learn
    ([False] * 8, 1.0, None),  # in profile
])
def test_a_rendered_person_is_labelled_front_behind_or_profile(image_left, offset, expected):
    keypoints = np.zeros((17, 3))
    for left, right in PAIRS:
        keypoints[left, 0], keypoints[right, 0] = offset / 4, -offset / 4
    annotation = {"left_is_image_left": image_left, "keypoints": keypoints.ravel().tolist(),
                  "amodal_bbox": [0.0, 0.0, 20.0, 60.0]}
    assert seen_from_front(annotation) is expected


def test_the_classifier_learns_which_way_people_face_and_the_same_seed_gives_the_same_weights(trained):
    assert trained.held_out_accuracy >= 0.95
    torch.set_num_threads(1)  # as the fixture trained: other tests' training sets the machine's
    again = train_facing(_crops(1024, 0), _crops(128, 1), seed=3, epochs=4, show_progress=False)
    for mine, theirs in zip(trained.net.state_dict().values(), again.net.state_dict().values(), strict=True):
        assert torch.equal(mine, theirs)


def test_the_distilled_classifier_learns_from_members_of_their_own_seeds_and_the_same_seed_gives_the_same_weights(
        monkeypatch):
    import vc.model.facing as facing

    torch.set_num_threads(1)
    seeds = []

    def recorded(train, held_out, seed, epochs, show_progress):
        seeds.append(seed)
        return train_facing(train, held_out, seed, epochs, show_progress)

    monkeypatch.setattr(facing, "train_facing", recorded)
    distilled = train_distilled_facing(_crops(1024, 0), _crops(128, 1), seed=3, members=2, epochs=4,
                                       show_progress=False)
    assert seeds == [3, 3 + MEMBER_SEED_STRIDE]
    assert len(distilled.members_held_out_accuracy) == 2
    assert distilled.held_out_accuracy >= 0.95
    measured = distilled.to_dict()["members_held_out_accuracy"]
    assert measured == [round(share, 4) for share in distilled.members_held_out_accuracy]
    again = train_distilled_facing(_crops(1024, 0), _crops(128, 1), seed=3, members=2, epochs=4, show_progress=False)
    for mine, theirs in zip(distilled.net.state_dict().values(), again.net.state_dict().values(), strict=True):
        assert torch.equal(mine, theirs)


def test_the_head_reader_learns_from_the_heads_colours_and_the_same_seed_gives_the_same_weights(headed):
    assert headed.held_out_accuracy >= 0.95 and headed.held_out_auc >= 0.98
    torch.set_num_threads(1)  # as the fixture trained: other tests' training sets the machine's
    again = train_head_colours(_crops(1024, 0), _crops(128, 1), seed=3)
    assert torch.equal(headed.net.logit.weight, again.net.logit.weight)


def test_the_head_reader_sees_only_the_head_and_not_how_bright_the_frame_is(headed):
    crops = _crops(8, 5).crops
    logits = _head_logits(headed, crops)
    clothed = crops.copy()
    clothed[:, HEAD_ROWS[1]:] = 255 - clothed[:, HEAD_ROWS[1]:]  # other clothes, other legs, other ground
    np.testing.assert_allclose(_head_logits(headed, clothed), logits, atol=1e-5)
    dimmer = np.rint(crops * 0.5 + 20).astype(np.uint8)  # a stop darker, and a little veiled
    np.testing.assert_allclose(_head_logits(headed, dimmer), logits, atol=0.1 * np.abs(logits).max())


def test_the_camera_s_look_is_drawn_from_the_generator_alone_and_leaves_the_crop_as_it_was():
    crop = np.random.default_rng(3).integers(0, 256, (64, 32, 3), dtype=np.uint8)
    kept = crop.copy()
    looks = [camera_look(crop, np.random.default_rng(seed)) for seed in range(40)]
    again = [camera_look(crop, np.random.default_rng(seed)) for seed in range(40)]
    assert all(look.shape == crop.shape and look.dtype == np.uint8 for look in looks)
    assert all(np.array_equal(look, repeated) for look, repeated in zip(looks, again, strict=True))
    np.testing.assert_array_equal(crop, kept)
    grey = [look for look in looks if (look == look[..., :1]).all()]
    assert 4 <= len(grey) <= 24  # monochrome three times in ten


def test_a_crop_moved_is_filled_from_its_own_edge():
    crop = np.arange(6 * 4 * 3, dtype=np.uint8).reshape(6, 4, 3)
    down = moved(crop, 2, 0)
    np.testing.assert_array_equal(down[2:], crop[:-2])
    np.testing.assert_array_equal(down[:2], crop[[0, 0]])
    left = moved(crop, 0, -1)
    np.testing.assert_array_equal(left[:, :-1], crop[:, 1:])
    np.testing.assert_array_equal(left[:, -1], crop[:, -1])
    np.testing.assert_array_equal(moved(crop, 0, 0), crop)


def test_small_people_are_read_front_or_behind_by_their_heads_and_tall_ones_by_the_classifier():
    classifier, head = np.array([4.0, 4.0, -2.0]), np.array([-1.0, -1.0, 0.5])
    heights = np.array([HEAD_READ_BELOW_PX - 1, HEAD_READ_BELOW_PX, 50.0])
    np.testing.assert_allclose(front_logits(classifier, head, heights),
                               [-1.0 + CLASSIFIER_WEIGHT_BELOW * 4.0, 4.0, 0.5 - CLASSIFIER_WEIGHT_BELOW * 2.0])
    np.testing.assert_array_equal(front_logits(classifier, None, heights), classifier)  # models before the head


def test_the_exported_model_with_the_head_reads_small_people_by_it(trained, headed):
    crops = _crops(4, 7)
    frame, boxes = pasted(crops.crops, (100, 200), 10, 45)  # people 58 px tall
    model = export_facing(trained.net, head=headed.net)
    reading = FacingReader(model).read(frame, boxes)
    session = ort.InferenceSession(model, providers=["CPUExecutionProvider"])
    classifier, head = session.run(None, {FRAME_INPUT: frame[None], ROIS_INPUT: crop_rois(boxes)})
    assert session.get_outputs()[1].name == HEAD_OUTPUT
    np.testing.assert_allclose(reading.front_logits, head + CLASSIFIER_WEIGHT_BELOW * classifier, rtol=1e-5)
    np.testing.assert_allclose(head, _head_logits(headed, crops.crops), rtol=0.1, atol=0.1)
    assert ((reading.front_logits > 0) == crops.front).all()
    tall = boxes.copy()
    tall[:, 3] = tall[:, 1] + HEAD_READ_BELOW_PX  # the same crops' rectangles' centres, people the gate's height
    tall_classifier = session.run(None, {FRAME_INPUT: frame[None], ROIS_INPUT: crop_rois(tall)})[0]
    mirror_classifier = session.run(None, dict(zip((FRAME_INPUT, ROIS_INPUT), mirrored(frame[None], crop_rois(tall)),
                                                   strict=True)))[0]
    np.testing.assert_allclose(FacingReader(model).read(frame, tall).front_logits,
                               (tall_classifier + mirror_classifier) / 2.0, rtol=1e-5)  # read twice (step 2)


def _mirror_image(frame: np.ndarray, boxes: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    width = frame.shape[1]
    return (np.ascontiguousarray(frame[:, ::-1]),
            np.stack([width - 1 - boxes[:, 2], boxes[:, 1], width - 1 - boxes[:, 0], boxes[:, 3]], axis=1))


def test_a_tall_person_and_their_mirror_image_face_the_same_way_and_turn_their_faces_apart(trained, turned, headed):
    crops = _turn_crops(4, 5)
    frame, boxes = pasted(crops.crops, (100, 200), 10, 45)
    boxes[:, 3] = boxes[:, 1] + MIRRORED_FROM_PX  # the same crops' rectangles' centres, people the gate's height
    reader = FacingReader(export_facing(trained.net, turned.net, headed.net))
    read, seen = reader.read(frame, boxes), reader.read(*_mirror_image(frame, boxes))
    np.testing.assert_allclose(seen.front_logits, read.front_logits, atol=1e-4)
    np.testing.assert_allclose(seen.across, -read.across, atol=1e-4)
    small = boxes.copy()
    small[:, 3] = small[:, 1] + MIRRORED_FROM_PX - 1  # read once: the mirror is another reading
    read, seen = reader.read(frame, small), reader.read(*_mirror_image(frame, small))
    assert np.abs(seen.across + read.across).max() > 1e-3


def test_the_exported_model_reads_the_frame_as_the_network_reads_its_crops(trained):
    crops = _crops(4, 7)
    frame, boxes = pasted(crops.crops, (100, 200), 10, 45)
    reader = FacingReader(export_facing(trained.net))
    reading = reader.read(frame, boxes)
    logits = reading.front_logits
    with torch.no_grad():
        expected = trained.net(torch.from_numpy(crops.crops).permute(0, 3, 1, 2).float() / 255.0).numpy()
    np.testing.assert_allclose(logits, expected, rtol=0.1, atol=0.05)  # 2 x 2 samples a pixel blur a little
    assert ((logits > 0) == crops.front).all()
    assert reading.across is None  # a model without the face turn reads the facing alone
    assert reader.read(frame, np.zeros((0, 4))).front_logits.shape == (0,)


def test_a_person_reads_the_same_alone_and_beside_others(trained, turned, headed):
    reader = FacingReader(export_facing(trained.net, turned.net, headed.net))
    frame = np.random.default_rng(5).integers(0, 256, (200, 330, 3)).astype(np.uint8)
    for boxes in (np.array([[251.37, 53.71, 301.9, 181.13], [3.29, 2.61, 40.77, 120.4]]),  # read twice
                  np.array([[251.37, 53.71, 271.9, 111.13], [3.29, 2.61, 20.77, 60.4]])):  # read by the head
        alone, together = reader.read(frame, boxes[:1]), reader.read(frame, boxes)
        assert together.front_logits[0] == alone.front_logits[0]  # to the last bit (0059)
        assert together.across[0] == alone.across[0]


def test_a_facing_reorders_the_pairs_and_becomes_the_handedness():
    keypoints = np.arange(17 * 3, dtype=np.float64).reshape(17, 3)
    # the networks ordered every pair as seen from behind (> 0): the image-left member is the left one
    behind = np.full(len(PAIRS), 0.2)
    same, handedness = ordered_by_facing(keypoints, behind, front_logit=-3.0)
    np.testing.assert_array_equal(same, keypoints)
    assert (handedness > 0.9).all()
    turned, handedness = ordered_by_facing(keypoints, behind, front_logit=3.0)
    for left, right in PAIRS:
        np.testing.assert_array_equal(turned[left], keypoints[right])
    assert (handedness < -0.9).all()
    np.testing.assert_array_equal(turned[0], keypoints[0])  # the nose has no pair


def _with_facing(bundle, trained, tmp_path, turned=None):
    run = tmp_path / "run"
    run.mkdir()
    (run / FACING_MODEL).write_bytes(export_facing(trained.net, None if turned is None else turned.net))
    (run / FACING_REPORT).write_text(json.dumps({**trained.to_dict(),
                                                 **({} if turned is None else {"face_turn": turned.to_dict()})}))
    manifest = json.loads((bundle / MANIFEST).read_text())
    files = {str(path.relative_to(bundle)): path.read_bytes() for path in bundle.rglob("*")
             if path.is_file() and path.name != MANIFEST}
    manifest, files = with_facing(manifest, files, run)
    faced = tmp_path / "faced"
    faced.mkdir()
    for name, data in {**files, MANIFEST: json.dumps(manifest).encode()}.items():
        (faced / name).parent.mkdir(parents=True, exist_ok=True)
        (faced / name).write_bytes(data)
    return faced


def test_a_bundle_carries_its_facing_model_checked_and_the_runtime_orders_people_by_it(bundle, trained, tmp_path):
    faced = _with_facing(bundle, trained, tmp_path)
    loaded = load_bundle(faced)
    assert loaded.facing is not None and load_bundle(bundle).facing is None
    frame = np.full((64, 128, 3), 120, np.uint8)
    frame[10:60, 20:40] = 40
    frame[12:22, 26:34] = (225, 185, 150)
    networks = np.array([0.4, -0.2, 0.3, 0.1, -0.5, 0.2, 0.6, 0.1])  # the networks' pairs, hedging
    keypoints = np.arange(17 * 3, dtype=np.float64).reshape(17, 3)
    people = [Person(region="r0", score=0.9, box=np.array([19.5, 9.5, 39.5, 59.5]), keypoints=keypoints.copy(),
                     mask=np.zeros((1, 1), bool), mask_origin=(0, 0), pair_handedness=networks.copy())]
    with Runtime(faced, threads=1) as runtime:
        people = runtime.runners[0].faced(frame, people)
    logit = FacingReader(loaded.facing).read(frame, np.array([people[0].box])).front_logits[0]
    # every pair ordered by one facing, of the model's confidence
    np.testing.assert_allclose(people[0].pair_handedness, -np.tanh(logit / 2.0), rtol=1e-6)
    # what a tracker weighs against an unclear walk stays the networks' confidence
    assert people[0].trusted_handedness == pytest.approx(networks.mean())
    with Runtime(bundle, threads=1) as plain:  # a bundle without the model keeps the networks' order
        kept = plain.runners[0].faced(frame, [Person(region="r0", score=0.9, box=np.array([19.5, 9.5, 39.5, 59.5]),
                                                      keypoints=keypoints.copy(), mask=np.zeros((1, 1), bool),
                                                      mask_origin=(0, 0), pair_handedness=networks.copy())])
    np.testing.assert_array_equal(kept[0].pair_handedness, networks)
    # a model that does not match its checksum is refused by name
    (faced / "models" / "facing.onnx").write_bytes(b"not the model")
    with pytest.raises(InputError, match=f"{FACING}.model_sha256"):
        load_bundle(faced)


def test_a_run_with_too_few_people_to_learn_from_trains_no_facing_model_and_says_why(tmp_path):
    from dataset_factory import write_dataset

    data = write_dataset(tmp_path / "dataset")
    report = train_facing_model(data, tmp_path / "run", seed=0, show_progress=False)
    assert "needs" in report["skipped"]
    assert not (tmp_path / "run" / FACING_MODEL).exists()


def test_the_classifier_is_small():
    assert sum(parameter.numel() for parameter in FacingNet().parameters()) < 40_000


def test_an_exported_bundle_ships_the_runs_facing_model(trained_run, trained, headed, tmp_path):
    from vc.cli.export import main as vc_export

    run = tmp_path / "run"
    shutil.copytree(trained_run, run)
    shutil.copytree(trained_run.parent / "dataset", tmp_path / "dataset")  # the run names its dataset beside it
    (run / FACING_MODEL).write_bytes(export_facing(trained.net, head=headed.net))
    (run / FACING_REPORT).write_text(json.dumps({**trained.to_dict(), "head_colours": headed.to_dict()}))
    assert vc_export([str(run), "-o", str(tmp_path / "bundle"), "--quiet"]) == 0
    manifest = json.loads((tmp_path / "bundle" / MANIFEST).read_text())
    assert manifest[FACING]["held_out_accuracy"] == trained.to_dict()["held_out_accuracy"]
    assert manifest[FACING]["head_output"] == HEAD_OUTPUT
    assert manifest[FACING]["head_held_out_auc"] == headed.to_dict()["held_out_auc"]
    assert load_bundle(tmp_path / "bundle").facing == (run / FACING_MODEL).read_bytes()


def test_boxes_of_no_size_or_beyond_the_frame_read_a_finite_facing(trained, headed):
    frame = np.zeros((100, 120, 3), np.uint8)
    boxes = np.array([[10.0, 10.0, 10.0, 10.0], [10.0, 10.0, 20.0, 10.0], [-50.0, -50.0, -10.0, -10.0],
                      [110.0, 90.0, 130.0, 140.0], [0.0, 0.0, 119.0, 99.0],
                      [-200.0, -300.0, -100.0, -100.0], [100.0, -50.0, 300.0, 400.0]])  # tall: read twice
    for model in (export_facing(trained.net), export_facing(trained.net, head=headed.net)):
        assert np.isfinite(FacingReader(model).read(frame, boxes).front_logits).all()  # a flat head reads its bias


def test_a_run_keeps_its_facing_model_only_for_the_renders_and_seed_it_was_trained_on(tmp_path, monkeypatch):
    from dataset_factory import write_dataset

    import vc.stages.train as stage

    data = write_dataset(tmp_path / "dataset")
    trained_calls = []

    def fake_train(train, held_out, seed, show_progress=True):  # as train_distilled_facing is called
        trained_calls.append(seed)
        return train_facing(_crops(1024, seed), _crops(128, 1), seed=seed, epochs=1, show_progress=False)

    def fake_turn(train, held_out, seed, show_progress=True):
        return train_face_turn(_turn_crops(256, seed), _turn_crops(64, 1), seed=seed, epochs=1, show_progress=False)

    def fake_head(train, held_out, seed):
        return train_head_colours(_crops(256, seed), _crops(64, 1), seed=seed)

    monkeypatch.setattr(stage, "MIN_FACING_CROPS", 0)
    monkeypatch.setattr(stage, "train_distilled_facing", fake_train)
    monkeypatch.setattr(stage, "train_face_turn", fake_turn)
    monkeypatch.setattr(stage, "train_head_colours", fake_head)
    run = tmp_path / "run"
    first = stage.train_facing_model(data, run, seed=0, show_progress=False)
    assert first["head_colours"]["held_out_auc"] > 0.9
    outputs = [output.name for output in ort.InferenceSession((run / FACING_MODEL).read_bytes()).get_outputs()]
    assert outputs[-1] == HEAD_OUTPUT
    assert stage.train_facing_model(data, run, seed=0, show_progress=False) == first  # resumed: kept
    stage.train_facing_model(data, run, seed=1, show_progress=False)  # another seed: trained again
    assert trained_calls == [0, 1]
    assert json.loads((run / FACING_REPORT).read_text())["trained_on"]["seed"] == 1


@pytest.mark.parametrize(("nose_ahead", "labelled", "expected"), [
    (FACE_AHEAD_OF_EARS["nose"], True, 1.0),  # in profile, facing the image's right
    (-0.5 * FACE_AHEAD_OF_EARS["nose"], True, -0.5),
    (-0.2, True, -1.0),  # further than any face: clipped
    (0.0, True, 0.0),  # along the view
    (0.05, False, None),  # no nose labelled
])
def test_a_rendered_persons_face_points_where_their_nose_stands_from_their_ears(nose_ahead, labelled, expected):
    height = 60.0
    keypoints = np.zeros((17, 3))
    keypoints[[0, 3, 4], 2] = 2
    keypoints[3, 0], keypoints[4, 0] = 10.0, 14.0
    keypoints[0, 0] = 12.0 + nose_ahead * height
    keypoints[0, 2] = 2 if labelled else 0
    annotation = {"keypoints": keypoints.ravel().tolist(), "amodal_bbox": [0.0, 0.0, 20.0, height]}
    assert face_across(annotation) == (None if expected is None else pytest.approx(expected))


def test_the_face_turn_learns_where_faces_point_and_the_same_seed_gives_the_same_weights(turned):
    assert turned.held_out_profile_sign >= 0.95
    assert turned.held_out_error < 0.6  # reading every face along the view would be 0.67 off
    torch.set_num_threads(1)  # as the fixture trained: other tests' training sets the machine's
    again = train_face_turn(_turn_crops(1024, 0), _turn_crops(128, 1), seed=3, epochs=4, show_progress=False)
    for mine, theirs in zip(turned.net.state_dict().values(), again.net.state_dict().values(), strict=True):
        assert torch.equal(mine, theirs)


def test_a_mirrored_face_points_the_other_way(turned):
    crops = _turn_crops(64, 5)
    profile = crops.across != 0
    batch = torch.from_numpy(crops.crops[profile]).permute(0, 3, 1, 2).float() / 255.0
    turned.net.eval()
    with torch.no_grad():
        read, mirrored = turned.net(batch).numpy(), turned.net(batch.flip(3)).numpy()
    assert (np.sign(read) == np.sign(crops.across[profile])).all()
    assert (np.sign(mirrored) == -np.sign(crops.across[profile])).all()
    assert np.abs(read).max() <= 1.0  # the net's tanh: where face_ahead takes it


def test_the_nose_and_eyes_are_put_where_the_face_points():
    keypoints = np.zeros((17, 3))
    keypoints[3, 0], keypoints[4, 0] = 50.0, 54.0  # ears
    keypoints[1, 0], keypoints[2, 0] = 51.0, 53.0  # eyes 2 px apart
    turned = face_ahead(keypoints, 100.0, -1.0)
    assert turned[0, 0] == pytest.approx(52.0 - FACE_AHEAD_OF_EARS["nose"] * 100.0)
    assert turned[[1, 2], 0].mean() == pytest.approx(52.0 - FACE_AHEAD_OF_EARS["eyes"] * 100.0)
    assert turned[2, 0] - turned[1, 0] == pytest.approx(2.0)  # their spacing kept
    np.testing.assert_array_equal(turned[3:], keypoints[3:])


def test_a_bundle_with_the_face_turn_turns_faces_each_frame(bundle, trained, turned, tmp_path):
    export = export_facing(trained.net, turned.net)
    reader = FacingReader(export)
    assert reader.reads_across
    crops = _turn_crops(3, 9)
    frame, boxes = pasted(crops.crops, (80, 140), 10, 45)
    across = reader.read(frame, boxes).across
    profile = crops.across != 0
    assert (np.sign(across[profile]) == np.sign(crops.across[profile])).all()
    assert (np.abs(across) <= 1.0).all()

    faced = _with_facing(bundle, trained, tmp_path, turned)
    manifest = json.loads((faced / MANIFEST).read_text())
    assert manifest[FACING]["across_output"] == "face_across"
    keypoints = np.zeros((17, 3))
    keypoints[:, 0], keypoints[:, 2] = 20.0, 1.0
    people = [Person(region="r0", score=0.9, box=np.array(box), keypoints=keypoints.copy(),
                     mask=np.zeros((1, 1), bool), mask_origin=(0, 0), pair_handedness=np.full(len(PAIRS), 0.5))
              for box in boxes]
    with Runtime(faced, threads=1) as runtime:
        people = runtime.runners[0].faced(frame, people)
    for person, points in zip(people, across, strict=True):  # the nose where the face turn put it, each frame
        height = person.box[3] - person.box[1]
        ears = person.keypoints[[3, 4], 0].mean()
        assert person.keypoints[0, 0] - ears == pytest.approx(FACE_AHEAD_OF_EARS["nose"] * height * points, abs=1e-4)
    assert any(abs(person.keypoints[0, 0] - 20.0) > 1.0 for person in people)  # profiles turned off the middle
