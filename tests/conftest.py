"""Shared fixtures: bundled scenes, the real PETS data (skipped with a reason when absent), test cameras."""

from __future__ import annotations

import importlib.util
import sys
from dataclasses import replace
from pathlib import Path
from types import ModuleType

import numpy as np
import pytest

from vc.calibration.camera import Camera, look_at
from vc.calibration.distortion import BrownConrady
from vc.model.config import network_config

REPO = Path(__file__).resolve().parents[1]
#: The example scenes: data in the repository, not in the package.
EXAMPLE_SCENES = REPO / "examples" / "scenes"
PETS_DATA = REPO.parent / "shared" / "data" / "pets09_s2l1"
TESTS_DATA = Path(__file__).resolve().parent / "data"

#: Oxford Town Centre intrinsics (Benfold & Reid, CVPR 2011), as published with the dataset.
TOWN_CENTRE = {"fx": 2696.35888671875, "fy": 2696.35888671875, "cx": 959.5, "cy": 539.5,
               "k1": -0.6015, "k2": 4.7020, "p1": -0.000475, "p2": -0.007823, "size": (1920, 1080)}


def load_script(path: Path, name: str) -> ModuleType:
    """A script of this repository (``packaging/runtime/build.py``) as a module: it is a script, not a package."""
    spec = importlib.util.spec_from_file_location(name, path)
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module  # dataclasses look their module up while it executes
    spec.loader.exec_module(module)
    return module


def write_compile_config(folder: Path, settings: dict) -> Path:
    """A ``vc-compile --config`` file holding ``settings`` (sections of :class:`vc.stages.config.CompileConfig`)."""
    import yaml

    path = folder / "budget.yaml"
    path.write_text(yaml.safe_dump(settings))
    return path


def rewrite_checkpoint(path: Path, edit) -> None:
    """Stand-in for a checkpoint another writer made, intact: its content edited in place by ``edit`` and its
    digest sealed again (a file edited without that is a damaged one, and refused as such)."""
    import torch

    from vc.model.trainer import content_digest

    content = torch.load(path, weights_only=True)
    content.pop("content_sha256", None)
    edit(content)
    torch.save({**content, "content_sha256": content_digest(content)}, path)


@pytest.fixture(scope="session")
def pets_data() -> Path:
    if not (PETS_DATA / "View_001.xml").is_file():
        pytest.skip(f"PETS 2009 S2.L1 data not found at {PETS_DATA} (development data, not shipped)")
    return PETS_DATA


@pytest.fixture(scope="session")
def pets_camera(pets_data: Path) -> Camera:
    from vc.calibration.readers import read_tsai_xml

    return read_tsai_xml(pets_data / "View_001.xml")


def town_centre_camera() -> Camera:
    tc = TOWN_CENTRE
    R, t = look_at([0.0, -12.0, 8.0], [0.0, 6.0, 0.0])
    K = np.array([[tc["fx"], 0, tc["cx"]], [0, tc["fy"], tc["cy"]], [0, 0, 1]])
    return Camera(*tc["size"], K=K, R=R, t=t, distortion=BrownConrady(tc["k1"], tc["k2"], tc["p1"], tc["p2"]))


def pixel_grid(camera: Camera, step: int = 16) -> np.ndarray:
    """A pixel grid that includes the four image corners and the borders (pixel centres)."""
    us = np.unique(np.r_[np.arange(0, camera.width, step), camera.width - 1]).astype(np.float64)
    vs = np.unique(np.r_[np.arange(0, camera.height, step), camera.height - 1]).astype(np.float64)
    return np.stack(np.meshgrid(us, vs), axis=-1).reshape(-1, 2)


#: A network small enough to train a few steps in a test.
SMALL = replace(network_config("fast"), name="small", width=16, residual_units=1, sb_reduction=2)


@pytest.fixture(scope="session")
def trained_run(tmp_path_factory) -> Path:
    """A finished two-step run of the small network on a flat test dataset (tests/dataset_factory.py)."""
    from dataset_factory import write_dataset

    from vc.model.trainer import RegionTrainer, TrainConfig
    from vc.render.dataset import open_region

    root = tmp_path_factory.mktemp("export")
    data_root = write_dataset(root / "dataset")
    run = root / "run"
    config = TrainConfig(network=SMALL, steps=2, batch_size=2, warmup_steps=1)
    RegionTrainer(open_region(data_root, "r0"), config, run, data_root, workers=0, show_progress=False).train()
    return run


@pytest.fixture(scope="session")
def bundle(trained_run, tmp_path_factory) -> Path:
    """The fp32 bundle of :func:`trained_run`."""
    from vc.cli.export import main as vc_export

    output = tmp_path_factory.mktemp("bundle") / "bundle"
    assert vc_export([str(trained_run), "-o", str(output), "--quiet"]) == 0
    return output


@pytest.fixture(scope="session")
def body_model():
    """anny bodies, built once per test session (a few seconds once anny's cache exists); test files that use
    it set ``pytestmark = pytest.mark.xdist_group("anny")`` so that a single xdist worker builds it."""
    from vc.render.bodies import BodyModel

    return BodyModel()
