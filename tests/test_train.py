"""Training: the loss on degenerate input, a one-batch overfit, byte-identical resume, the windows it trains on,
vc-train's outputs and its refusals (another scene's checkpoint, a region not in the dataset, too few shards)."""

from __future__ import annotations

import json
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
import torch
from conftest import rewrite_checkpoint
from dataset_factory import INPUT_SIZE, write_dataset

import vc.model.trainer as vc_model_train
from vc.cli.train import main as vc_train
from vc.deploy.heatmaps import (
    CENTRE_OFFSET_CHANNELS,
    FINE_CENTRE_CHANNELS,
    FINE_CHANNELS,
    HEAD_CHANNELS,
    HEATMAP_CHANNELS,
    MASK_CHANNEL,
    OFFSET_CHANNELS,
)
from vc.errors import InputError
from vc.model.codec import CodecConfig, encode
from vc.model.config import DEFAULT_ARCH, network_config
from vc.model.data import CropPolicy, TrainingStream
from vc.model.loss import LossWeights, heatmap_terms, scene_pose_loss
from vc.model.network import ScenePoseNet
from vc.model.trainer import (
    RegionTrainer,
    TrainConfig,
    checkpoint_path,
    data_workers,
    forward,
    learning_rate_factor,
    load_checkpoint,
)
from vc.render.dataset import open_region

SMALL = replace(network_config("fast"), name="small", width=16, residual_units=1, sb_reduction=2)


@pytest.fixture(scope="module")
def flat_dataset(tmp_path_factory) -> Path:
    return write_dataset(tmp_path_factory.mktemp("flat") / "dataset")


def _config(**overrides) -> TrainConfig:
    return TrainConfig(network=SMALL, **{"steps": 4, "batch_size": 2, "checkpoint_every": 2, "warmup_steps": 1,
                                 "crop": CropPolicy(size=(64, 64)), **overrides})


@pytest.mark.parametrize("value", [0.0, 1.0])
def test_loss_is_finite_on_empty_targets_and_constant_images(value):
    torch.manual_seed(0)
    net = ScenePoseNet(SMALL)
    outputs = net(torch.full((2, 3, 64, 64), value))
    loss, terms = scene_pose_loss(outputs, torch.zeros(2, HEATMAP_CHANNELS, 16, 16))
    loss.backward()
    assert torch.isfinite(loss) and all(np.isfinite(v) for v in terms.values())
    assert all(torch.isfinite(p.grad).all() for p in net.parameters() if p.grad is not None)


def test_loss_weights_scale_their_own_terms():
    prediction, targets = torch.rand(2, HEATMAP_CHANNELS, 8, 8), torch.rand(2, HEATMAP_CHANNELS, 8, 8)
    terms = heatmap_terms(prediction, targets)
    outputs = {"heatmaps": prediction, "beliefs": [prediction]}  # one belief stage + the final maps
    loss, _ = scene_pose_loss(outputs, targets, LossWeights(detection=2.0, pose=3.0, segmentation=5.0,
                                                            handedness=7.0))
    expected = 2 * (2.0 * terms["detection"] + 3.0 * terms["pose"] + 5.0 * terms["segmentation"]
                    + 7.0 * terms["handedness"])
    assert float(loss) == pytest.approx(float(expected), rel=1e-6)
    assert float(terms["pose"]) == pytest.approx(float((prediction[:, 1:18] - targets[:, 1:18]).square().mean()))


def test_centre_offsets_are_learned_on_people_only_and_the_codec_sets_the_network_s_maps():
    prediction, targets = torch.rand(2, OFFSET_CHANNELS, 8, 8), torch.rand(2, OFFSET_CHANNELS, 8, 8)
    targets[:, MASK_CHANNEL, :4] = 0.0  # nobody in the top half: its offsets are not learned
    terms = heatmap_terms(prediction, targets)
    shifted = prediction.clone()
    shifted[:, CENTRE_OFFSET_CHANNELS, :4] += 1.0
    assert float(heatmap_terms(shifted, targets)["centre_offsets"]) == pytest.approx(float(terms["centre_offsets"]))
    shifted[:, CENTRE_OFFSET_CHANNELS, 4:] += 1.0
    assert float(heatmap_terms(shifted, targets)["centre_offsets"]) > float(terms["centre_offsets"])
    with_offsets = _config(codec=CodecConfig(centre_offsets=True))
    assert with_offsets.network.heatmap_channels == with_offsets.network.belief_channels == OFFSET_CHANNELS
    assert TrainConfig.from_dict(with_offsets.to_dict()) == with_offsets
    with pytest.raises(ValueError, match="centre offsets"):
        TrainConfig(network=with_offsets.network)


def test_the_fine_centre_map_is_weighed_as_the_centre_map_and_the_codec_sets_the_network_s_maps():
    prediction, targets = torch.rand(2, FINE_CHANNELS, 8, 8), torch.rand(2, FINE_CHANNELS, 8, 8)
    terms = heatmap_terms(prediction, targets)
    assert float(terms["fine_centre"]) == pytest.approx(
        float((prediction[:, FINE_CENTRE_CHANNELS] - targets[:, FINE_CENTRE_CHANNELS]).square().mean()))
    assert "fine_centre" not in heatmap_terms(prediction[:, :OFFSET_CHANNELS], targets[:, :OFFSET_CHANNELS])
    weights = LossWeights(detection=2.0)
    loss, _ = scene_pose_loss({"beliefs": [], "heatmaps": prediction}, targets, weights)
    without, _ = scene_pose_loss({"beliefs": [], "heatmaps": prediction}, targets, replace(weights, detection=0.0))
    # alpha weighs each of the two centre maps' errors: the coarse map's share is what it is without the fine one
    assert float(loss - without) == pytest.approx(2.0 * float(terms["detection"] + terms["fine_centre"]), rel=1e-5)
    coarse_only, _ = scene_pose_loss({"beliefs": [], "heatmaps": prediction[:, :OFFSET_CHANNELS]},
                                     targets[:, :OFFSET_CHANNELS], weights)
    coarse_without, _ = scene_pose_loss({"beliefs": [], "heatmaps": prediction[:, :OFFSET_CHANNELS]},
                                        targets[:, :OFFSET_CHANNELS], replace(weights, detection=0.0))
    assert float(coarse_only - coarse_without) == pytest.approx(2.0 * float(terms["detection"]), rel=1e-5)
    fine = _config(codec=CodecConfig(centre_offsets=True, fine_centre=True))
    assert fine.network.heatmap_channels == FINE_CHANNELS
    assert TrainConfig.from_dict(fine.to_dict()) == fine
    with pytest.raises(ValueError, match="centre offsets"):
        CodecConfig(fine_centre=True)


def test_one_batch_overfits_tenfold():
    rng = np.random.default_rng(0)
    images, targets = [], []
    for _ in range(4):  # bright upright blobs on a dark ground, labelled with the real codec
        image = np.full((64, 64, 3), 0.2, np.float32)
        instances = np.zeros((64, 64), np.uint8)
        x, y = rng.uniform(12, 52), rng.uniform(20, 44)
        image[int(y) - 16:int(y) + 16, int(x) - 5:int(x) + 5] = 0.9
        instances[int(y) - 16:int(y) + 16, int(x) - 5:int(x) + 5] = 1
        keypoints = np.column_stack([np.full(17, x), np.linspace(y - 15, y + 15, 17), np.full(17, 2)])
        annotation = {"center": [x, y], "keypoints": keypoints.ravel().tolist(), "amodal_bbox": [x - 5, y - 16, 10, 32]}
        images.append(image.transpose(2, 0, 1))
        targets.append(encode([annotation], instances, CodecConfig()))
    images, targets = torch.from_numpy(np.stack(images)), torch.from_numpy(np.stack(targets))
    torch.manual_seed(0)
    net = ScenePoseNet(SMALL)
    optimizer = torch.optim.Adam(net.parameters(), lr=3e-3)
    losses = []
    for _ in range(150):
        loss, _ = scene_pose_loss(net(images), targets)
        optimizer.zero_grad()
        loss.backward()
        optimizer.step()
        losses.append(loss.item())
    assert min(losses[-10:]) < losses[0] / 10


def test_learning_rate_warms_up_then_decays_to_zero():
    config = _config(steps=100, warmup_steps=10)
    factors = [learning_rate_factor(step, config) for step in range(101)]
    assert factors[0] == pytest.approx(0.1) and factors[9] == pytest.approx(1.0)
    assert all(a >= b for a, b in zip(factors[10:], factors[11:], strict=False)) and factors[100] == pytest.approx(0.0)


def test_training_windows_are_on_the_stride_grid_and_deterministic(flat_dataset):
    data = open_region(flat_dataset, "r0")
    stream = TrainingStream(data.train, CodecConfig(), INPUT_SIZE, CropPolicy(size=(64, 32)), seed=5)
    image, targets = stream[3]
    assert image.shape == (3, 32, 64) and targets.shape == (HEATMAP_CHANNELS, 8, 16)
    assert torch.equal(stream[3][0], image) and not torch.equal(stream[4][0], image)
    # Draw k of epoch e is a permutation: every sample exactly once per epoch.
    assert sorted(stream.sample_index(k) for k in range(len(stream))) == list(range(len(stream)))
    # A window's targets are the whole input's targets cut at the same place.
    sample = data.train[stream.sample_index(3)]
    full = TrainingStream([sample], CodecConfig(), INPUT_SIZE, crop=None, augmentation=None)[0][1]
    assert any(torch.equal(targets, full[:, y:y + 8, x:x + 16]) for y in range(0, 9) for x in range(0, 17))


def test_resumed_training_ends_with_identical_weights(flat_dataset, tmp_path):
    config = _config()
    straight = RegionTrainer(open_region(flat_dataset, "r0"), config, tmp_path / "straight", flat_dataset,
                             workers=0, show_progress=False)
    straight.train()
    interrupted = RegionTrainer(open_region(flat_dataset, "r0"), config, tmp_path / "resumed", flat_dataset,
                                workers=0, show_progress=False)
    interrupted.train(until=2)
    assert torch.load(checkpoint_path(tmp_path / "resumed", "r0"), weights_only=True)["step"] == 2
    resumed = RegionTrainer(open_region(flat_dataset, "r0"), config, tmp_path / "resumed", flat_dataset,
                            workers=1, show_progress=False)
    assert resumed.step == 2
    resumed.train()
    for name, tensor in straight.net.state_dict().items():
        assert torch.equal(tensor, resumed.net.state_dict()[name]), name
    assert straight.history == resumed.history


def test_a_network_with_the_head_map_learns_it_and_its_held_out_people_are_decoded(flat_dataset, tmp_path):
    config = _config(codec=CodecConfig(centre_offsets=True, fine_centre=True, head_map=True))
    assert config.network.heatmap_channels == HEAD_CHANNELS
    assert TrainConfig.from_dict(config.to_dict()) == config
    trainer = RegionTrainer(open_region(flat_dataset, "r0"), config, tmp_path / "run", flat_dataset, workers=0,
                            show_progress=False)
    trainer.train()
    assert np.isfinite(trainer.history["loss"]).all()
    assert load_checkpoint(checkpoint_path(tmp_path / "run", "r0")).config.codec.head_map
    with torch.no_grad():
        assert trainer.net(torch.zeros(1, 3, 64, 64))["heatmaps"].shape[1] == HEAD_CHANNELS
    assert trainer.evaluate().region == "r0"  # held-out renders decoded with step 5


def test_bf16_autocast_in_channels_last_trains_fp32_weights_and_resumes_identically(flat_dataset, tmp_path):
    """The fast compute settings keep what the trainer promises: fp32 weights, outputs close to the fp32
    forward pass, and a resumed run ending on the same weights as a straight one."""
    config = _config(bf16_autocast=True, channels_last=True)
    straight = RegionTrainer(open_region(flat_dataset, "r0"), config, tmp_path / "straight", flat_dataset,
                             workers=0, show_progress=False)
    straight.train()
    assert all(tensor.dtype == torch.float32 and torch.isfinite(tensor).all()
               for tensor in straight.net.state_dict().values() if tensor.is_floating_point())
    interrupted = RegionTrainer(open_region(flat_dataset, "r0"), config, tmp_path / "resumed", flat_dataset,
                                workers=0, show_progress=False)
    interrupted.train(until=2)
    resumed = RegionTrainer(open_region(flat_dataset, "r0"), config, tmp_path / "resumed", flat_dataset,
                            workers=0, show_progress=False)
    resumed.train()
    for name, tensor in straight.net.state_dict().items():
        assert torch.equal(tensor, resumed.net.state_dict()[name]), name
    images = torch.rand(2, 3, 64, 64).contiguous(memory_format=torch.channels_last)
    fast = forward(straight.net.eval(), images, config)["heatmaps"]
    exact = forward(straight.net, images, _config())["heatmaps"]
    assert fast.dtype == torch.float32 and (fast - exact).abs().max() < 0.05 * exact.abs().max() + 1e-3


def test_resuming_with_other_settings_is_refused(flat_dataset, tmp_path):
    RegionTrainer(open_region(flat_dataset, "r0"), _config(), tmp_path, flat_dataset, workers=0,
                  show_progress=False).train(until=2)
    with pytest.raises(InputError, match="learning_rate 0.002 -> 0.01"):
        RegionTrainer(open_region(flat_dataset, "r0"), _config(learning_rate=0.01), tmp_path, flat_dataset)


def _rewrite_stored_config(path: Path, edit) -> None:
    rewrite_checkpoint(path, lambda content: edit(content["train_config"]))


def test_a_stored_config_missing_a_newer_field_resumes_with_its_default(flat_dataset, tmp_path):
    """A field added after a checkpoint was written takes its default (which reproduces the old behaviour), so
    the run resumes; a run that asks for another value is told which field differs."""
    RegionTrainer(open_region(flat_dataset, "r0"), _config(), tmp_path, flat_dataset, workers=0,
                  show_progress=False).train(until=2)
    _rewrite_stored_config(checkpoint_path(tmp_path, "r0"), lambda config: config["loss"].pop("handedness"))
    resumed = RegionTrainer(open_region(flat_dataset, "r0"), _config(), tmp_path, flat_dataset, workers=0,
                            show_progress=False)
    assert resumed.step == 2
    with pytest.raises(InputError, match="loss.handedness 1.0 -> 2.0"):
        RegionTrainer(open_region(flat_dataset, "r0"), _config(loss=LossWeights(handedness=2.0)), tmp_path,
                      flat_dataset)


@pytest.mark.parametrize(("edit", "field", "reason"), [
    (lambda config: config["crop"].update(jitter=0.5), "train_config.crop.jitter", "Unexpected keyword argument"),
    (lambda config: config["network"].update(stem_stride=3), "train_config.network", "stem_stride must be one of"),
    (lambda config: config.update(steps="many"), "train_config.steps", "valid integer"),
])
def test_a_stored_config_this_version_cannot_read_names_the_file_and_field(flat_dataset, tmp_path, capsys, edit,
                                                                          field, reason):
    RegionTrainer(open_region(flat_dataset, "r0"), _config(), tmp_path, flat_dataset, workers=0,
                  show_progress=False).train(until=2)
    path = checkpoint_path(tmp_path, "r0")
    _rewrite_stored_config(path, edit)
    with pytest.raises(InputError) as error:
        load_checkpoint(path)
    assert error.value.path == str(path) and error.value.field == field and reason in error.value.reason
    assert vc_train([str(flat_dataset), "-o", str(tmp_path), "--quiet", "--workers", "0"]) == 2
    assert f"{path}: {field}: " in capsys.readouterr().err


def test_the_output_stride_is_the_network_s_alone():
    """Codec and decoder take the network's stride whatever they were given, so the three never disagree."""
    stride_one = replace(SMALL, stem_stride=1)
    config = TrainConfig(network=stride_one, codec=CodecConfig(stride=4))
    assert config.codec.stride == config.decode.stride == 1
    assert TrainConfig.from_dict(config.to_dict()) == config


def test_vc_train_writes_checkpoints_metrics_and_curves(flat_dataset, tmp_path, capsys):
    run = tmp_path / "run"
    assert vc_train([str(flat_dataset), "-o", str(run), "--steps", "3", "--batch-size", "2", "--quiet",
                     "--workers", "0"]) == 0
    metrics = json.loads((run / "metrics.json").read_text())
    region = metrics["regions"]["r0"]
    assert region["steps"] == 3 and region["ground_truth"] > 0 and 0.0 <= region["ap50"] <= 1.0
    assert metrics["scene_hash"] == json.loads((flat_dataset / "manifest.json").read_text())["scene_hash"]
    for image in ("precision_recall.png", "r0/precision_recall.png", "r0/training_loss.png"):
        assert (run / image).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    checkpoint = torch.load(checkpoint_path(run, "r0"), weights_only=True)
    assert TrainConfig.from_dict(checkpoint["train_config"]).network == network_config(DEFAULT_ARCH)
    assert "AP50" in capsys.readouterr().out


def test_a_checkpoint_from_another_scene_is_refused(flat_dataset, tmp_path, capsys):
    run = tmp_path / "run"
    RegionTrainer(open_region(flat_dataset, "r0"), _config(), run, flat_dataset, workers=0,
                  show_progress=False).train(until=2)
    other = write_dataset(tmp_path / "other", scene_hash="0" * 64)
    with pytest.raises(InputError, match="belongs to scene"):
        RegionTrainer(open_region(other, "r0"), _config(), run, other)
    assert vc_train([str(other), "-o", str(run), "--quiet"]) == 2
    assert "belongs to scene 'flat'" in capsys.readouterr().err


def test_a_region_not_in_the_dataset_exits_with_status_2(flat_dataset, tmp_path, capsys):
    assert vc_train([str(flat_dataset), "-o", str(tmp_path / "run"), "--region", "r9"]) == 2
    assert "region r9 is not in this dataset (it has r0)" in capsys.readouterr().err
    assert not (tmp_path / "run").exists()


def test_a_step_count_below_one_is_an_argument_error(flat_dataset, tmp_path, capsys):
    with pytest.raises(SystemExit) as exit_status:
        vc_train([str(flat_dataset), "-o", str(tmp_path / "run"), "--steps", "0"])
    assert exit_status.value.code == 2 and "must be at least 1" in capsys.readouterr().err


def test_a_dataset_with_one_shard_is_refused(tmp_path, capsys):
    single = write_dataset(tmp_path / "single", samples=4, shard_size=8)
    assert vc_train([str(single), "-o", str(tmp_path / "run")]) == 2
    assert "needs at least 2" in capsys.readouterr().err


def test_width_and_sb_units_override_the_preset(flat_dataset, tmp_path):
    run = tmp_path / "run"
    assert vc_train([str(flat_dataset), "-o", str(run), "--steps", "1", "--batch-size", "2", "--quiet",
                     "--workers", "0", "--width", "16", "--sb-units", "1"]) == 0
    network = TrainConfig.from_dict(torch.load(checkpoint_path(run, "r0"), weights_only=True)["train_config"]).network
    assert (network.width, network.sb_units) == (16, 1)


def test_a_width_the_bottleneck_cannot_divide_is_refused(flat_dataset, tmp_path, capsys):
    assert vc_train([str(flat_dataset), "-o", str(tmp_path / "run"), "--width", "15"]) == 2
    assert "sb_reduction must be >= 1 and divide width 15" in capsys.readouterr().err


@pytest.mark.parametrize(("cores", "gpu_workers", "cpu_workers"),
                         [(16, 12, 1), (64, 12, 1), (6, 4, 1), (4, 2, 1), (2, 1, 0), (1, 1, 0)])
def test_data_workers_feed_a_gpu_from_every_core_but_two(monkeypatch, cores: int, gpu_workers: int,
                                                        cpu_workers: int) -> None:
    monkeypatch.setattr(vc_model_train, "usable_cores", lambda: cores)
    assert data_workers(torch.device("cuda")) == gpu_workers
    # On the CPU the step takes the cores: on two a loader process only stalls its threads, so none.
    assert data_workers(torch.device("cpu")) == cpu_workers
