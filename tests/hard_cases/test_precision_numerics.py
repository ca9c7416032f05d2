"""fp16 and int8 exports against fp32 on the same frames at the edges of what a camera sends: black, white,
constant, a single bright pixel, high-contrast stripes, noise. Every precision stays finite and in the range of
the maps; fp16 stays within a small fraction of fp32's range everywhere. How far int8 may drift is not a
numerical question but an accuracy one: ``--precision auto`` keeps it only where held-out accuracy holds
(``tests/test_export.py``)."""

from __future__ import annotations

import numpy as np
import onnxruntime as ort
import pytest
import torch
from conftest import SMALL
from dataset_factory import write_dataset
from hard_case_settings import PROPERTY
from hypothesis import given
from hypothesis import strategies as st

from vc.model.export import export_onnx
from vc.model.network import ScenePoseNet
from vc.model.precision import to_fp16, to_int8
from vc.render.dataset import open_region

SIZE = (64, 64)  # width, height of the crop


@pytest.fixture(scope="module")
def sessions(tmp_path_factory) -> dict[str, ort.InferenceSession]:
    torch.manual_seed(0)
    fp32 = export_onnx(ScenePoseNet(SMALL), SIZE, SIZE, {})
    calibration = open_region(write_dataset(tmp_path_factory.mktemp("calibration") / "dataset"), "r0").train[:8]
    models = {"fp32": fp32, "fp16": to_fp16(fp32), "int8": to_int8(fp32, calibration, SIZE)}
    return {name: ort.InferenceSession(model, providers=["CPUExecutionProvider"]) for name, model in models.items()}


@st.composite
def frames(draw) -> np.ndarray:
    kind = draw(st.sampled_from(["constant", "single pixel", "stripes", "noise"]))
    level = draw(st.integers(0, 255))
    frame = np.full((SIZE[1], SIZE[0], 3), level, np.uint8)
    if kind == "single pixel":
        frame[draw(st.integers(0, SIZE[1] - 1)), draw(st.integers(0, SIZE[0] - 1))] = 255 - level
    elif kind == "stripes":
        frame[:, ::draw(st.integers(2, 8))] = 255 - level
    elif kind == "noise":
        frame = np.random.default_rng(draw(st.integers(0, 2**32 - 1))).integers(0, 256, frame.shape, np.uint8)
    return frame


@PROPERTY
@given(frame=frames())
def test_every_precision_stays_finite_and_fp16_stays_with_fp32(sessions, frame):
    maps = {name: session.run(None, {"crop": frame[None]})[0] for name, session in sessions.items()}
    for name, values in maps.items():
        assert np.isfinite(values).all(), name
        assert values.min() >= -1.0 - 1e-3 and values.max() <= 1.0 + 1e-3, name
    spread = max(float(maps["fp32"].max() - maps["fp32"].min()), 1e-3)
    assert np.abs(maps["fp16"] - maps["fp32"]).max() <= 5e-3 * spread + 1e-3
