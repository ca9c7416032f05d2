"""A non-finite loss stops training with one clear line, keeping the last good checkpoint; nothing non-finite
reaches a checkpoint."""

from __future__ import annotations

import pytest
import torch
from conftest import SMALL
from dataset_factory import write_dataset

from vc.errors import StageError
from vc.model import trainer as train_module
from vc.model.trainer import RegionTrainer, TrainConfig, checkpoint_path, load_checkpoint
from vc.render.dataset import open_region


def test_a_diverging_loss_stops_training_and_keeps_the_last_good_checkpoint(tmp_path, monkeypatch):
    data_root = write_dataset(tmp_path / "dataset")
    real_loss, calls = train_module.scene_pose_loss, []

    def diverging(*args, **kwargs):
        loss, parts = real_loss(*args, **kwargs)
        calls.append(1)
        return (loss * float("nan"), parts) if len(calls) > 2 else (loss, parts)

    monkeypatch.setattr(train_module, "scene_pose_loss", diverging)
    config = TrainConfig(network=SMALL, steps=5, batch_size=2, warmup_steps=1, checkpoint_every=1)
    trainer = RegionTrainer(open_region(data_root, "r0"), config, tmp_path / "run", data_root, workers=0,
                            show_progress=False)
    with pytest.raises(StageError, match=r"r0: the training loss became nan at step 2 .* step 2\) is kept"):
        trainer.train()
    kept = load_checkpoint(checkpoint_path(tmp_path / "run", "r0"))
    assert kept.step == 2
    assert all(torch.isfinite(tensor).all() for tensor in kept.content["model"].values())
