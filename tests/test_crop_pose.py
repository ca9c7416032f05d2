"""The keypoint model: each person's keypoints read again from their own crop (vc.model.crop_pose,
vc.deploy.crop_pose)."""

from __future__ import annotations

import json
import shutil
from dataclasses import dataclass

import numpy as np
import onnx
import onnxruntime as ort
import pytest
import torch
from crop_factory import pasted

from vc.deploy.bundle import CROP_POSE, MANIFEST, load_bundle, sha256
from vc.deploy.crop_pose import (
    CROP_SIZE,
    MAP_STRIDE,
    MAPS_OUTPUT,
    MIN_READ_HEIGHT_PX,
    PEAK_FLOOR,
    CropPoseReader,
    keypoints_of_maps,
    mirrored_back,
    with_crop_keypoints,
)
from vc.deploy.facing import CROP_MARGIN, FRAME_INPUT, ROIS_INPUT, crop_rois, frame_part
from vc.deploy.facing import mirrored as mirrored_input
from vc.deploy.heatmaps import PAIRS, swap_pairs
from vc.deploy.runtime import Person, Runtime
from vc.errors import InputError
from vc.model.crop_pose import (
    CROP_POSE_MODEL,
    CROP_POSE_REPORT,
    CropPoseNet,
    PoseCrops,
    crops_of,
    dataset_crops,
    heatmap_targets,
    mirrored,
    train_crop_pose,
)
from vc.model.crop_precision import keypoints_at_int8, read_crops, to_int8
from vc.model.export import export_crop_pose
from vc.stages.train import train_crop_pose_model


def _crops(count: int, seed: int) -> PoseCrops:
    """Crops of a bright square on a dark ground, every keypoint at the square, somewhere in the crop."""
    rng = np.random.default_rng(seed)
    crops = rng.integers(0, 40, (count, CROP_SIZE[1], CROP_SIZE[0], 3)).astype(np.uint8)
    keypoints = np.zeros((count, 17, 3), np.float32)
    for crop, points in zip(crops, keypoints, strict=True):
        x, y = rng.integers(3, CROP_SIZE[0] - 3), rng.integers(3, CROP_SIZE[1] - 3)
        crop[y - 2:y + 3, x - 2:x + 3] = 230
        points[:] = (x, y, 2)
    return PoseCrops(crops, keypoints, np.full(count, 80.0, np.float32))


@pytest.fixture(scope="module")
def trained():
    """Two training steps: enough to check the wiring; what the model learns is measured on renders
    (docs/decisions/0039-keypoints-from-the-crop.md), where it takes thousands."""
    torch.set_num_threads(1)
    return train_crop_pose(_crops(128, 0), _crops(32, 1), seed=3, samples=128, show_progress=False)


def test_a_heat_maps_peak_is_read_back_at_the_frame_pixel_it_stands_for():
    rois = np.array([[100.0, 50.0, 148.0, 146.0], [10.0, 20.0, 34.0, 68.0]])  # crop pixels 1 and 0.5 frame px
    maps = np.zeros((2, 17, CROP_SIZE[1] // MAP_STRIDE, CROP_SIZE[0] // MAP_STRIDE), np.float32)
    maps[:, 5, 10, 7] = 1.0  # the shoulder's cell (7, 10): crop pixels 14.5, 20.5 at its centre
    keypoints = keypoints_of_maps(maps, rois)
    assert keypoints[0, 5] == pytest.approx([100.0 + 14.5, 50.0 + 20.5, 1.0])
    assert keypoints[1, 5] == pytest.approx([10.0 + 15.0 * 0.5 - 0.5, 20.0 + 21.0 * 0.5 - 0.5, 1.0])
    maps[0, 5, 10, 8] = 0.5  # a larger neighbour on the right moves it a quarter cell there
    assert keypoints_of_maps(maps, rois)[0, 5, 0] == pytest.approx(100.0 + 14.5 + 0.25 * MAP_STRIDE)


def test_the_targets_read_back_where_the_keypoints_are():
    crops = _crops(8, 4)
    crops.keypoints[:, :, :2] += np.random.default_rng(0).uniform(-0.5, 0.5, (8, 17, 2))  # between pixels too
    targets, labelled = heatmap_targets(crops.keypoints)
    whole = np.repeat([[0.0, 0.0, CROP_SIZE[0], CROP_SIZE[1]]], 8, axis=0)
    read = keypoints_of_maps(targets.numpy(), whole)
    assert np.abs(read[..., :2] - crops.keypoints[..., :2]).max() <= MAP_STRIDE / 2
    assert labelled.numpy().all()


def test_training_measures_the_model_on_the_held_out_crops_and_the_same_seed_gives_the_same_weights(trained):
    assert trained.train_crops == 128 and trained.held_out_crops == 32
    assert 0.0 <= trained.held_out_pckh <= 1.0 and len(trained.held_out_pckh_per_keypoint) == 17
    again = train_crop_pose(_crops(128, 0), _crops(32, 1), seed=3, samples=128, show_progress=False)
    for name, value in trained.net.state_dict().items():
        assert torch.equal(value, again.net.state_dict()[name]), name


def test_training_in_bf16_channels_last_is_seeded_too_and_exports_a_model_that_reads_as_it_does():
    """The region networks' compute where the CPU has bf16 instructions (0006), which the keypoint model was measured
    in (0052): the same seed gives the same weights, and the exported graph (fp32, NCHW) reads the crops as the
    channels-last network does."""
    def bf16(seed):
        return train_crop_pose(_crops(128, 0), _crops(32, 1), seed=seed, samples=128, bf16_autocast=True,
                               channels_last=True, show_progress=False)

    first, again = bf16(3), bf16(3)
    for name, value in first.net.state_dict().items():
        assert torch.equal(value, again.net.state_dict()[name]), name
    assert 0.0 <= first.held_out_pckh <= 1.0
    reading = _exported_and_network_maps(first.net)
    assert np.corrcoef(reading.maps.ravel(), reading.expected.ravel())[0, 1] > 0.95


def test_a_mirror_moves_each_keypoint_across_and_exchanges_each_pairs_image_order():
    crops = _crops(2, 5)
    flipped_crops, flipped = mirrored(crops.crops, crops.keypoints)
    np.testing.assert_array_equal(flipped_crops[:, :, ::-1], crops.crops)
    left, right = PAIRS[2]  # the shoulders
    assert flipped[0, left, 0] == pytest.approx(CROP_SIZE[0] - 1 - crops.keypoints[0, right, 0])
    assert flipped[0, 0, 0] == pytest.approx(CROP_SIZE[0] - 1 - crops.keypoints[0, 0, 0])  # the nose stays itself


@dataclass
class ExportedReading:
    """Three crops pasted in a frame, read by a network's exported model (``maps``) and by the network itself
    (``expected``)."""

    reader: CropPoseReader
    frame: np.ndarray
    boxes: np.ndarray
    part: np.ndarray
    shifted: np.ndarray
    maps: np.ndarray
    expected: np.ndarray


def _exported_and_network_maps(net: CropPoseNet) -> ExportedReading:
    crops = _crops(3, 7)
    frame, boxes = pasted(crops.crops, (110, 200), 4, 60)
    reader = CropPoseReader(export_crop_pose(net))
    part, shifted = frame_part(frame, crop_rois(boxes))
    maps = reader.session.run([MAPS_OUTPUT], {FRAME_INPUT: part, ROIS_INPUT: shifted})[0]
    net.eval()
    with torch.no_grad():
        expected = net(torch.from_numpy(crops.crops).permute(0, 3, 1, 2).float() / 255.0).numpy()
    return ExportedReading(reader, frame, boxes, part, shifted, maps, expected)


def test_the_exported_model_reads_the_frame_as_the_network_reads_its_crops(trained):
    reading = _exported_and_network_maps(trained.net)
    reader, frame, boxes, part, shifted = reading.reader, reading.frame, reading.boxes, reading.part, reading.shifted
    maps, expected = reading.maps, reading.expected
    assert maps.shape == expected.shape == (3, 17, CROP_SIZE[1] // MAP_STRIDE, CROP_SIZE[0] // MAP_STRIDE)
    assert np.corrcoef(maps.ravel(), expected.ravel())[0, 1] > 0.95  # 2 x 2 samples a pixel blur a little
    seen = reader.session.run([MAPS_OUTPUT], dict(zip((FRAME_INPUT, ROIS_INPUT), mirrored_input(part, shifted),
                                                      strict=True)))[0]
    read = reader.read(frame, boxes)  # the crop's maps and its mirror's, averaged
    np.testing.assert_allclose(read, keypoints_of_maps((maps + mirrored_back(seen)) / 2.0, crop_rois(boxes)),
                               atol=1e-4)
    assert reader.read(frame, np.zeros((0, 4))).shape == (0, 17, 3)


def test_a_person_and_their_mirror_image_are_read_as_each_others_mirror(trained):
    crops = _crops(3, 7)
    frame, boxes = pasted(crops.crops, (110, 200), 4, 60)
    reader = CropPoseReader(export_crop_pose(trained.net))
    read = reader.read(frame, boxes)
    width = frame.shape[1]
    mirror_boxes = np.stack([width - 1 - boxes[:, 2], boxes[:, 1], width - 1 - boxes[:, 0], boxes[:, 3]], axis=1)
    seen = reader.read(np.ascontiguousarray(frame[:, ::-1]), mirror_boxes)
    seen[..., 0] = width - 1 - seen[..., 0]  # back to the frame's pixels: pairs now the other way round
    np.testing.assert_allclose(swap_pairs(seen, np.ones((len(seen), len(PAIRS)), bool)), read, atol=1e-3)


def _noise_frame_and_two_people() -> tuple[np.ndarray, np.ndarray]:
    """A frame of noise and two people's boxes at fractional pixels, far apart: cut from one part of the frame, the
    first person's crop would be sampled from another origin than alone."""
    frame = np.random.default_rng(5).integers(0, 256, (200, 330, 3)).astype(np.uint8)
    return frame, np.array([[251.37, 53.71, 301.9, 181.13], [3.29, 2.61, 40.77, 120.4]])


def test_a_person_reads_the_same_alone_and_beside_others(trained):
    reader = CropPoseReader(export_crop_pose(trained.net))
    frame, boxes = _noise_frame_and_two_people()
    alone = reader.read(frame, boxes[:1])
    np.testing.assert_array_equal(reader.read(frame, boxes)[:1], alone)  # to the last bit (0059)
    np.testing.assert_array_equal(reader.read(frame, boxes[::-1])[1:], alone)


def test_the_keypoint_model_at_int8_reads_the_crops_as_fp32_does(trained):
    model = export_crop_pose(trained.net)
    chosen = keypoints_at_int8(model, _crops(128, 0), _crops(32, 1), seed=0)
    crops = _crops(8, 2).crops
    fp32, int8 = (read_crops(graph, crops, MAPS_OUTPUT) for graph in (model, to_int8(model, crops)))
    assert np.corrcoef(fp32.ravel(), int8.ravel())[0, 1] > 0.95
    assert chosen.precision in ("int8", "fp32") and set(chosen.measured) == {"fp32", "int8"}


def test_the_keypoints_take_the_order_the_persons_facing_gave_and_keep_their_confidences():
    keypoints = np.zeros((17, 3))
    keypoints[:, 2] = np.linspace(0.1, 0.9, 17)
    image_ordered = np.tile(np.arange(17.0)[:, None], (1, 3))  # keypoint k at x = y = k
    image_ordered[:, 2] = 1.0  # the model sure of each
    left, right = PAIRS[4]  # the wrists
    from_behind = with_crop_keypoints(keypoints, image_ordered, np.full(len(PAIRS), 0.7))
    from_front = with_crop_keypoints(keypoints, image_ordered, np.full(len(PAIRS), -0.7))
    assert from_behind[left, 0] == left and from_behind[right, 0] == right  # behind: the image-left one is the left
    assert from_front[left, 0] == right and from_front[right, 0] == left
    assert from_front[0, 0] == 0  # the nose is no pair
    np.testing.assert_array_equal(from_front[:, 2], keypoints[:, 2])
    unsure = image_ordered.copy()
    unsure[3, 2] = PEAK_FLOOR - 0.01  # an ear the model is not sure of keeps the network's place
    assert with_crop_keypoints(keypoints, unsure, np.full(len(PAIRS), 0.7))[3, 0] == keypoints[3, 0]
    assert with_crop_keypoints(keypoints, unsure, np.full(len(PAIRS), 0.7))[4, 0] == 4.0
    crossed = keypoints.copy()
    crossed[left, 0], crossed[right, 0] = 5.0, 1.0  # no handedness: the person's own x order stands in
    assert with_crop_keypoints(crossed, image_ordered, None)[left, 0] == right


def test_boxes_of_no_size_or_beyond_the_frame_read_finite_keypoints(trained):
    reader = CropPoseReader(export_crop_pose(trained.net))
    frame = np.zeros((100, 120, 3), np.uint8)
    boxes = np.array([[10.0, 10.0, 10.0, 10.0], [-50.0, -50.0, -10.0, -10.0], [110.0, 90.0, 130.0, 140.0]])
    assert np.isfinite(reader.read(frame, boxes)).all()


def test_rendered_people_are_cut_with_their_keypoints_where_the_crop_shows_them(tmp_path):
    from dataset_factory import write_dataset

    from vc.render.dataset import open_region

    data = open_region(write_dataset(tmp_path / "dataset"), "r0")
    crops = crops_of(data.train, np.random.default_rng(0))
    assert len(crops) > 0 and crops.crops.shape[1:] == (CROP_SIZE[1], CROP_SIZE[0], 3)
    labelled = crops.keypoints[..., 2] > 0
    inside = ((crops.keypoints[..., 0] > -1) & (crops.keypoints[..., 0] < CROP_SIZE[0])
              & (crops.keypoints[..., 1] > -1) & (crops.keypoints[..., 1] < CROP_SIZE[1]))
    assert inside[labelled].mean() > 0.95  # a whole person's keypoints fall in their crop
    # a whole person fills about 1 / 1.1 of the crop's height
    assert np.median(crops.heights) == pytest.approx(CROP_SIZE[1] / CROP_MARGIN, rel=0.15)


def test_a_compile_learns_from_the_people_tall_enough_in_its_frame_to_be_read(tmp_path):
    from dataset_factory import write_dataset

    from vc.render.dataset import open_region, read_manifest

    data = write_dataset(tmp_path / "dataset")
    region = read_manifest(data)["regions"]["r0"]
    scale = region["input_size"][1] / region["crop_window"][3]
    whole = crops_of(open_region(data, "r0").train, np.random.default_rng(0))
    frame_heights = np.sort([annotation["amodal_bbox"][3] / scale for sample in open_region(data, "r0").train
                             for annotation in sample.annotations])
    gate = float(np.median(frame_heights))
    train, held_out = dataset_crops(data, seed=0, min_frame_height=gate)
    assert 0 < len(train) + len(held_out) and len(train) < len(whole)
    assert len(dataset_crops(data, seed=0, min_frame_height=frame_heights[-1] + 1.0)[0]) == 0


def test_a_bundle_carries_its_keypoint_model_checked_and_the_runtime_reads_people_again(bundle, trained, tmp_path,
                                                                                          monkeypatch):
    import vc.deploy.crop_pose

    monkeypatch.setattr(vc.deploy.crop_pose, "PEAK_FLOOR", -1.0)  # two training steps: sure of nothing yet
    tall = _crops(1, 9).crops.repeat(2, axis=1).repeat(2, axis=2)  # a person 175 px tall
    frame, boxes = pasted(tall, (200, 128), 4, 60)
    keypoints = np.zeros((17, 3))
    keypoints[:, 2] = 0.5

    def person(weak: bool = False, box: np.ndarray = boxes[0]) -> Person:
        return Person(region="r0", score=0.9, box=box.copy(), keypoints=keypoints.copy(),
                      mask=np.zeros((1, 1), bool), mask_origin=(0, 0), pair_handedness=np.full(len(PAIRS), 0.5),
                      weak=weak)

    read = tmp_path / "bundle"
    shutil.copytree(bundle, read)
    model = export_crop_pose(trained.net)
    (read / "models" / "crop_pose.onnx").write_bytes(model)
    manifest = json.loads((read / MANIFEST).read_text())
    manifest[CROP_POSE] = {"model": "models/crop_pose.onnx", "model_sha256": sha256(model)}
    (read / MANIFEST).write_text(json.dumps(manifest))
    assert load_bundle(read).crop_pose == model and load_bundle(bundle).crop_pose is None
    short_box = boxes[0] + np.array([0.0, 0.0, 0.0, MIN_READ_HEIGHT_PX - 1.0 - (boxes[0, 3] - boxes[0, 1])])
    with Runtime(read, threads=1) as runtime:
        seen, weak, short = runtime.runners[0].faced(frame, [person(), person(weak=True), person(box=short_box)])
    expected = CropPoseReader(model).read(frame, boxes)[0]
    np.testing.assert_allclose(seen.keypoints[:, :2], expected[:, :2])  # seen from behind: image order is theirs
    np.testing.assert_array_equal(seen.keypoints[:, 2], keypoints[:, 2])
    np.testing.assert_array_equal(weak.keypoints, keypoints)  # a weak person, for a tracker's eyes, keeps its own
    np.testing.assert_array_equal(short.keypoints, keypoints)  # too short for the model: the network's places
    with Runtime(bundle, threads=1) as plain:  # a bundle without the model keeps the networks' keypoints
        kept = plain.runners[0].faced(frame, [person()])[0]
    np.testing.assert_array_equal(kept.keypoints, keypoints)
    (read / "models" / "crop_pose.onnx").write_bytes(b"not the model")
    with pytest.raises(InputError, match=f"{CROP_POSE}.model_sha256"):
        load_bundle(read)


def test_a_run_with_too_few_people_to_learn_from_trains_no_keypoint_model_and_says_why(tmp_path):
    from dataset_factory import write_dataset

    data = write_dataset(tmp_path / "dataset")
    report = train_crop_pose_model(data, tmp_path / "run", seed=0, show_progress=False)
    assert "needs" in report["skipped"]
    assert not (tmp_path / "run" / CROP_POSE_MODEL).exists()


def test_a_run_keeps_its_keypoint_model_only_for_the_renders_and_seed_it_was_trained_on(tmp_path, monkeypatch):
    from dataset_factory import write_dataset

    import vc.stages.train as stage

    data = write_dataset(tmp_path / "dataset")
    trained_calls = []

    def fake_train(train, held_out, seed, show_progress=True):
        trained_calls.append(seed)
        return train_crop_pose(_crops(128, seed), _crops(16, 1), seed=seed, samples=128, show_progress=False)

    monkeypatch.setattr(stage, "MIN_CROP_POSE_CROPS", 0)
    monkeypatch.setattr(stage, "train_crop_pose", fake_train)
    run = tmp_path / "run"
    first = stage.train_crop_pose_model(data, run, seed=0, show_progress=False)
    assert first["precision"] in ("int8", "fp32")  # measured both ways on the held-out crops the run has
    assert set(first["held_out_pckh_by_precision"]) <= {"fp32", "int8"}
    shipped = ort.InferenceSession((run / CROP_POSE_MODEL).read_bytes(), providers=["CPUExecutionProvider"])
    assert any(node.op_type == "QuantizeLinear" for node in onnx.load_from_string(
        (run / CROP_POSE_MODEL).read_bytes()).graph.node) == (first["precision"] == "int8")
    assert shipped.get_outputs()[0].name == MAPS_OUTPUT
    assert stage.train_crop_pose_model(data, run, seed=0, show_progress=False) == first  # resumed: kept
    stage.train_crop_pose_model(data, run, seed=1, show_progress=False)  # another seed: trained again
    monkeypatch.setattr(stage, "SAMPLES_SEEN", stage.SAMPLES_SEEN // 2)
    stage.train_crop_pose_model(data, run, seed=1, show_progress=False)  # another schedule: trained again
    assert trained_calls == [0, 1, 1]
    assert json.loads((run / CROP_POSE_REPORT).read_text())["trained_on"]["seed"] == 1


def test_an_exported_bundle_ships_the_runs_keypoint_model(trained_run, trained, tmp_path):
    from vc.cli.export import main as vc_export

    run = tmp_path / "run"
    shutil.copytree(trained_run, run)
    shutil.copytree(trained_run.parent / "dataset", tmp_path / "dataset")  # the run names its dataset beside it
    (run / CROP_POSE_MODEL).write_bytes(export_crop_pose(trained.net))
    (run / CROP_POSE_REPORT).write_text(json.dumps({**trained.to_dict(), "precision": "int8"}))
    assert vc_export([str(run), "-o", str(tmp_path / "bundle"), "--quiet"]) == 0
    manifest = json.loads((tmp_path / "bundle" / MANIFEST).read_text())
    assert manifest[CROP_POSE]["precision"] == "int8"  # as the run's training chose
    assert manifest[CROP_POSE]["held_out_pckh"] == trained.to_dict()["held_out_pckh"]
    assert manifest[CROP_POSE]["crop_size"] == list(CROP_SIZE)
    assert load_bundle(tmp_path / "bundle").crop_pose == (run / CROP_POSE_MODEL).read_bytes()


def test_the_keypoint_model_is_small():
    assert sum(parameter.numel() for parameter in CropPoseNet().parameters()) < 250_000


def test_a_compile_trains_the_keypoint_model_where_most_of_its_people_are_tall_enough_to_be_read(tmp_path,
                                                                                                 monkeypatch):
    from dataset_factory import write_dataset

    import vc.stages.train as stage
    from vc.cli.train import _parser
    from vc.model.crop_pose import frame_heights
    from vc.stages.config import PRESETS, TrainSettings

    assert TrainSettings().crop_pose == "auto"  # docs/decisions/0040-keypoint-model-by-size.md
    assert all(preset.train.crop_pose == "auto" for preset in PRESETS.values())
    assert _parser().parse_args(["renders", "-o", "run"]).crop_pose == "auto"
    assert _parser().parse_args(["renders", "-o", "run", "--no-crop-pose"]).crop_pose is False
    data = write_dataset(tmp_path / "dataset")
    heights = frame_heights(data)
    run = tmp_path / "run"
    run.mkdir()
    (run / CROP_POSE_MODEL).write_bytes(b"a model from an earlier run")
    gate = float(np.percentile(heights, 60))  # about 40 % tall enough
    monkeypatch.setattr(stage, "MIN_READ_HEIGHT_PX", gate)
    report = stage.train_crop_pose_model(data, run, seed=0, wanted="auto", show_progress=False)
    assert f"{(heights >= gate).mean():.0%} of the scene's whole rendered people" in report["skipped"]
    assert "train.crop_pose: true" in report["skipped"]
    assert not (run / CROP_POSE_MODEL).exists()  # an export would have shipped it
    trained = []
    monkeypatch.setattr(stage, "MIN_READ_HEIGHT_PX", float(np.percentile(heights, 40)))  # 60 % tall enough
    monkeypatch.setattr(stage, "MIN_CROP_POSE_CROPS", 0)
    monkeypatch.setattr(stage, "train_crop_pose", lambda train, held_out, seed, show_progress=True: trained.append(
        len(train)) or train_crop_pose(_crops(128, seed), _crops(16, 1), seed=seed, samples=128,
                                       show_progress=False))
    assert "skipped" not in stage.train_crop_pose_model(data, run, seed=0, wanted="auto", show_progress=False)
    assert trained and (run / CROP_POSE_MODEL).is_file()
    assert "not asked for" in stage.train_crop_pose_model(data, run, seed=0, wanted=False)["skipped"]
    assert not (run / CROP_POSE_MODEL).exists()
