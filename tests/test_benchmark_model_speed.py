"""The model-speed benchmark times what vc-train does: its training step must run on each preset's own output maps."""

from __future__ import annotations

import pytest

from benchmarks import model_speed
from vc.model.config import PRESETS


@pytest.mark.parametrize("arch", ["fast", "fast-dw", "dense9"])
def test_the_timed_training_step_runs_on_the_networks_own_heat_map_layout(arch):
    """The targets once kept the 19 anatomical maps after the networks gained handedness maps (27), and the
    benchmark stopped at its first step."""
    assert model_speed.training_images_per_second(PRESETS[arch], (64, 64), batch=2, repetitions=1) > 0
    assert model_speed.inference_ms(PRESETS[arch], (64, 64), repetitions=1) > 0


def test_compute_settings_are_timed_and_reported(tmp_path):
    import json

    model_speed.compare_compute((64, 64), batch=2, steps=1, out=tmp_path)
    report = json.loads((tmp_path / "model_speed_compute.json").read_text())
    assert [row["compute"] for row in report["results"]] == list(model_speed.TRAINING_COMPUTE)
    assert all(rate > 0 for row in report["results"] for rate in row["images_per_second"])
    assert report["results"][0]["vs_fp32"] == 1.0 and "| bf16 channels-last |" in (
        tmp_path / "model_speed_compute.md").read_text()
