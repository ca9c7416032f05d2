"""The model-speed benchmark times what vc-train does: its training step must run on each preset's own output maps."""

from __future__ import annotations

import pytest
from conftest import load_benchmark

from vc.model.config import PRESETS

model_speed = load_benchmark("model_speed")


@pytest.mark.parametrize("arch", ["fast", "fast-dw", "dense9"])
def test_the_timed_training_step_runs_on_the_networks_own_heat_map_layout(arch):
    """The targets once kept the 19 anatomical maps after the networks gained handedness maps (27), and the
    benchmark stopped at its first step."""
    assert model_speed.training_images_per_second(PRESETS[arch], (64, 64), batch=2, repetitions=1) > 0
    assert model_speed.inference_ms(PRESETS[arch], (64, 64), repetitions=1) > 0
