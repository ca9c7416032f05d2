"""Reading vc-render output for training: split by shard, targets from labels, clear errors on bad shards."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import numpy as np
import pytest
from conftest import EXAMPLE_SCENES

from vc.deploy.heatmaps import CENTRE_CHANNEL, HANDEDNESS_CHANNELS, HEATMAP_CHANNELS, MASK_CHANNEL, PAIRS
from vc.errors import InputError
from vc.model.codec import CodecConfig
from vc.model.data import Augmentation, TrainingStream
from vc.render.dataset import CHECKSUMS, open_region
from vc.render.job import RenderRequest, render_dataset
from vc.render.plan import plan_render
from vc.render.synthesis import SynthesisSettings
from vc.scenes.loader import load_scene
from vc.scenes.regions import plan_regions

pytestmark = pytest.mark.xdist_group("anny")


@pytest.fixture(scope="module")
def small_dataset(tmp_path_factory, body_model) -> Path:
    scene = load_scene(EXAMPLE_SCENES / "demo" / "scene.yaml")
    root = tmp_path_factory.mktemp("train-data")
    regions = plan_regions(scene)
    render_dataset(RenderRequest(scene=scene, regions=regions[:1], samples=6, settings=SynthesisSettings(spp=2),
                                 plan=plan_render(scene, regions, time_costs=False), output=root, shard_size=3),
                   bodies=body_model, show_progress=False)
    return root


def test_the_last_shard_is_held_out(small_dataset) -> None:
    data = open_region(small_dataset, "r0")
    assert len(data.train) == 3 and len(data.held_out) == 3
    assert {s.image_path.parent.parent.name for s in data.held_out} == {"shard-00001"}
    assert data.input_size == tuple(json.loads((small_dataset / "manifest.json").read_text())["regions"]["r0"][
        "input_size"])


def test_items_are_images_and_their_encoded_labels(small_dataset) -> None:
    data = open_region(small_dataset, "r0")
    dataset = TrainingStream(data.train, CodecConfig(stride=4), data.input_size, crop=None, augmentation=None)
    width, height = data.input_size
    people = 0
    for draw in range(len(dataset)):
        index = dataset.sample_index(draw)
        image, targets = dataset[draw]
        assert image.shape == (3, height, width) and 0.0 <= float(image.min()) and float(image.max()) <= 1.0
        assert targets.shape == (HEATMAP_CHANNELS, height // 4, width // 4)
        annotations = data.train[index].annotations
        people += len(annotations)
        centre_inside = any(a["center"] is not None and 0 <= a["center"][0] < width and 0 <= a["center"][1] < height
                            for a in annotations)
        assert (float(targets[CENTRE_CHANNEL].max()) > 0.5) == centre_inside
        if annotations:
            assert float(targets[MASK_CHANNEL].max()) > 0.0
            assert float(targets[HANDEDNESS_CHANNELS].abs().max()) > 0.0
    assert people > 0


def test_image_order_of_keypoint_pairs_agrees_with_the_labels(small_dataset) -> None:
    """The order comes from the 3-D keypoints through the region camera; where both members are labelled and
    apart, it must be the order of their labelled pixels."""
    data = open_region(small_dataset, "r0")
    compared = 0
    for sample in data.train + data.held_out:
        for annotation in sample.annotations:
            keypoints = np.reshape(annotation["keypoints"], (-1, 3))
            for (left, right), left_first in zip(PAIRS, annotation["left_is_image_left"], strict=True):
                labelled = keypoints[left, 2] > 0 and keypoints[right, 2] > 0
                if labelled and abs(keypoints[left, 0] - keypoints[right, 0]) > 0.01:
                    assert left_first == (keypoints[left, 0] < keypoints[right, 0])
                    compared += 1
    assert compared > 20


def test_augmentation_is_deterministic_per_draw(small_dataset) -> None:
    data = open_region(small_dataset, "r0")
    dataset = TrainingStream(data.train, CodecConfig(), data.input_size, crop=None, augmentation=Augmentation(),
                             seed=3)
    first, again = dataset[0][0], dataset[0][0]
    assert np.array_equal(first.numpy(), again.numpy())
    # The same sample drawn again in the next epoch gets other jitter.
    later = next(draw for draw in range(len(dataset), 2 * len(dataset))
                 if dataset.sample_index(draw) == dataset.sample_index(0))
    assert not np.array_equal(first.numpy(), dataset[later][0].numpy())


def test_each_draw_is_the_same_item_in_any_order_of_draws(small_dataset) -> None:
    """A data-loader worker draws its share of a batch out of order and across epoch boundaries; a resumed run
    starts mid-epoch. Whatever the order, draw k is the same item (the stream keeps its epoch's order between
    draws), so the run's bytes do not depend on how the draws were shared out."""
    data = open_region(small_dataset, "r0")

    def stream() -> TrainingStream:
        return TrainingStream(data.train, CodecConfig(), data.input_size, seed=3)

    count = len(data.train)
    draws = [0, 1, count + 2, 3, 2 * count + 1, count, 1]
    in_order, shuffled = stream(), stream()
    expected = {draw: in_order[draw] for draw in sorted(set(draws))}
    for draw in draws:
        image, targets = shuffled[draw]
        assert image.numpy().tobytes() == expected[draw][0].numpy().tobytes()
        assert targets.numpy().tobytes() == expected[draw][1].numpy().tobytes()
    # and the order of an epoch is its own: the seed's generator for (seed, epoch)
    assert [shuffled.sample_index(count + k) for k in range(count)] == \
        np.random.default_rng([3, 1]).permutation(count).tolist()


def _broken_copy(small_dataset: Path, tmp_path: Path) -> Path:
    copy = tmp_path / "copy"
    shutil.copytree(small_dataset, copy)
    return copy


SHARD_DAMAGE = [
    (lambda root: (root / "r0" / "shard-00000" / "annotations.json").write_text("{not json"), "corrupt shard"),
    (lambda root: (root / "r0" / "shard-00000" / "annotations.json").unlink(), "shard has no annotations"),
    (lambda root: (root / "r0" / "shard-00000" / "images" / "000001.png").unlink(), "missing from its shard"),
    (lambda root: (root / "r0" / "shard-00000" / "annotations.json").write_text(
        json.dumps({"images": [], "annotations": []})), "shard holds no samples"),
]


@pytest.mark.parametrize(("damage", "message"), SHARD_DAMAGE)
def test_damaged_shards_are_refused_by_their_checksums(small_dataset, tmp_path, damage, message) -> None:
    copy = _broken_copy(small_dataset, tmp_path)
    damage(copy)
    with pytest.raises(InputError, match=f"does not match the shard's {CHECKSUMS}"):
        open_region(copy, "r0")


@pytest.mark.parametrize(("damage", "message"), [*SHARD_DAMAGE, (lambda root: (root / "manifest.json").unlink(),
                                                                  "not a vc-render dataset")])
def test_bad_shards_of_a_dataset_without_checksums_are_named_in_one_clear_error(small_dataset, tmp_path, damage,
                                                                                message) -> None:
    """Datasets written before shards carried checksums (format 2) are read unchecked, but not blindly."""
    copy = _broken_copy(small_dataset, tmp_path)
    manifest = json.loads((copy / "manifest.json").read_text())
    (copy / "manifest.json").write_text(json.dumps({**manifest, "format_version": 2}))
    damage(copy)
    with pytest.raises(InputError, match=message):
        open_region(copy, "r0")


def test_a_region_not_in_the_dataset_is_refused(small_dataset) -> None:
    with pytest.raises(InputError, match="region 'r7' is not in this dataset"):
        open_region(small_dataset, "r7")
