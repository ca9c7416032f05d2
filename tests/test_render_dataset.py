"""vc-render end to end on the bundled demo scene: labels agree with pixels, COCO tools accept the dataset,
a crashed run resumes to the same bytes, and bad input is refused with exit status 2.

The label checks run on a few hundred rendered people (issue 3's acceptance): every box is its visible mask's
bounding box; at least 99% of visible (v = 2) keypoints lie in the person's mask dilated by 2 px; every
occluded (v = 1) keypoint has a surface in front of it in the depth pass.
"""

from __future__ import annotations

import contextlib
import io
import json
import shutil
from pathlib import Path

import cv2
import numpy as np
import pytest
from conftest import EXAMPLE_SCENES
from pycocotools.coco import COCO
from pycocotools.cocoeval import COCOeval
from scene_factory import base_scene, write_scene

from vc.cli import render as render_cli
from vc.errors import EXIT_BAD_INPUT, InputError
from vc.io import read_image
from vc.render import dataset, job
from vc.render.job import RenderRequest, render_dataset
from vc.render.plan import plan_render
from vc.render.synthesis import RegionSynthesizer, SynthesisSettings
from vc.scenes.loader import load_scene
from vc.scenes.regions import plan_regions

pytestmark = pytest.mark.xdist_group("anny")

DEMO = EXAMPLE_SCENES / "demo" / "scene.yaml"
#: Samples per region for the label checks: about 300 people over the demo's two regions.
LABEL_SAMPLES = 60


@pytest.fixture(scope="module")
def demo_scene():
    return load_scene(DEMO)


@pytest.fixture(scope="module")
def demo_plan(demo_scene):
    return plan_render(demo_scene, plan_regions(demo_scene), time_costs=False)


@pytest.fixture(scope="module")
def labelled_samples(demo_scene, demo_plan, body_model) -> list[tuple[RegionSynthesizer, object]]:
    settings = SynthesisSettings(spp=8)
    samples = []
    for region in plan_regions(demo_scene):
        synthesizer = RegionSynthesizer(demo_scene, region, body_model, settings, demo_plan)
        samples += [(synthesizer, synthesizer.sample(index)) for index in range(LABEL_SAMPLES)]
    return samples


def test_there_are_a_few_hundred_people_in_varied_situations(labelled_samples) -> None:
    annotations = [a for _, sample in labelled_samples for a in sample.annotations]
    assert len(annotations) >= 200
    kinds = {a["attributes"]["placement"] for a in annotations}
    assert {"region", "border"} <= kinds
    heights = [a["attributes"]["height_m"] for a in annotations]
    assert 1.5 <= min(heights) and max(heights) <= 1.95
    assert any(a["num_keypoints"] < 17 for a in annotations), "nobody is cut or occluded"


def test_every_box_is_its_visible_masks_bounding_box(labelled_samples) -> None:
    for _, sample in labelled_samples:
        for annotation in sample.annotations:
            rows, columns = np.nonzero(sample.instances == annotation["instance_id"])
            assert annotation["area"] == len(rows)
            expected = [columns.min() - 0.5, rows.min() - 0.5, columns.max() - columns.min() + 1.0,
                        rows.max() - rows.min() + 1.0]
            assert annotation["bbox"] == expected


def test_visible_keypoints_lie_in_the_dilated_mask(labelled_samples) -> None:
    kernel = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (5, 5))  # radius 2 px
    inside = total = 0
    for _, sample in labelled_samples:
        for annotation in sample.annotations:
            mask = cv2.dilate((sample.instances == annotation["instance_id"]).astype(np.uint8), kernel) > 0
            keypoints = np.asarray(annotation["keypoints"]).reshape(-1, 3)
            for u, v, visibility in keypoints:
                if visibility == 2:
                    total += 1
                    inside += bool(mask[int(round(v)), int(round(u))])
    assert total >= 1000
    assert inside / total >= 0.99, f"{inside}/{total} visible keypoints inside their masks"


def test_occluded_keypoints_are_behind_something_in_the_depth_pass(labelled_samples) -> None:
    occluded = 0
    for synthesizer, sample in labelled_samples:
        for annotation in sample.annotations:
            keypoints = np.asarray(annotation["keypoints"]).reshape(-1, 3)
            depth = synthesizer.camera.world_to_camera(np.asarray(annotation["attributes"]["keypoints_m"]))[:, 2]
            for (u, v, visibility), keypoint_depth in zip(keypoints, depth, strict=True):
                if visibility == 1:
                    occluded += 1
                    assert sample.depth[int(round(v)), int(round(u))] < keypoint_depth
    assert occluded >= 50

@pytest.fixture(scope="module")
def rendered_dataset(tmp_path_factory, demo_scene, body_model) -> Path:
    root = tmp_path_factory.mktemp("dataset")
    request = _request(demo_scene, root, samples=12)
    render_dataset(request, bodies=body_model, show_progress=False)
    return root


#: Render plans by scene hash: a plan takes seconds (the light is estimated), and every request here shares one.
_PLANS: dict = {}


def _request(scene, root: Path, samples: int) -> RenderRequest:
    regions = plan_regions(scene)
    if scene.content_hash not in _PLANS:
        _PLANS[scene.content_hash] = plan_render(scene, regions, time_costs=False)
    return RenderRequest(scene=scene, regions=regions, samples=samples, settings=SynthesisSettings(spp=4),
                         plan=_PLANS[scene.content_hash], output=root, shard_size=5)


def test_dataset_layout_and_manifest(rendered_dataset, demo_scene) -> None:
    manifest = json.loads((rendered_dataset / "manifest.json").read_text())
    assert manifest["scene_hash"] == demo_scene.content_hash
    assert set(manifest["regions"]) == {region.name for region in plan_regions(demo_scene)}
    for name, region in manifest["regions"].items():
        assert region["counts"]["samples"] == 12 and region["shards"] == 3
        shards = sorted(path.name for path in (rendered_dataset / name).iterdir())
        assert shards == ["shard-00000", "shard-00001", "shard-00002"]
        last = rendered_dataset / name / "shard-00002"
        assert sorted(p.name for p in (last / "images").iterdir()) == ["000010.png", "000011.png"]
        image = read_image(last / "images" / "000010.png")
        assert image.shape == (region["input_size"][1], region["input_size"][0], 3)
    assert {e["name"] for e in manifest["effects"]} >= {"lens_distortion", "shadows"}
    assert manifest["response"] == {"name": "srgb", "identified": True, "reason": "given by the scene", "edges": 0,
                                    "misfits": {}}
    summary = json.loads((rendered_dataset / "render_summary.json").read_text())
    assert summary["dataset"] == {name: region["counts"] for name, region in manifest["regions"].items()}


def test_pycocotools_reads_the_annotations_and_self_evaluation_is_perfect(rendered_dataset) -> None:
    for path in sorted(rendered_dataset.glob("*/shard-*/annotations.json")):
        with contextlib.redirect_stdout(io.StringIO()):
            truth = COCO(str(path))
            if not truth.getAnnIds():
                continue
            detections = [{**a, "score": 1.0} for a in truth.loadAnns(truth.getAnnIds())]
            for iou_type in ("keypoints", "bbox", "segm"):
                evaluation = COCOeval(truth, truth.loadRes(detections), iou_type)
                evaluation.evaluate()
                evaluation.accumulate()
                evaluation.summarize()
                assert evaluation.stats[0] == pytest.approx(1.0), (path, iou_type)
        category = truth.loadCats(1)[0]
        assert len(category["keypoints"]) == 17 and len(category["skeleton"]) == 19


def test_masks_on_disk_match_the_annotations(rendered_dataset) -> None:
    from pycocotools import mask as coco_mask

    for path in sorted(rendered_dataset.glob("*/shard-*/annotations.json")):
        document = json.loads(path.read_text())
        for image in document["images"]:
            instances = read_image(path.parent / image["mask_file"])[..., 0]
            for annotation in (a for a in document["annotations"] if a["image_id"] == image["id"]):
                rle = {**annotation["segmentation"], "counts": annotation["segmentation"]["counts"].encode()}
                np.testing.assert_array_equal(coco_mask.decode(rle).astype(bool),
                                              instances == annotation["instance_id"])


def _tree(root: Path) -> dict[str, bytes]:
    return {str(path.relative_to(root)): path.read_bytes() for path in sorted(root.rglob("*"))
            if path.is_file() and path.name != "render_summary.json"}


def test_a_crashed_run_resumes_to_the_same_bytes(tmp_path, demo_scene, body_model, rendered_dataset,
                                                 monkeypatch) -> None:
    crashed = tmp_path / "crashed"
    real_write_shard = dataset.write_shard
    written = []

    def crash_in_the_second_shard(root, shard, samples, info):
        if written:  # the first shard completes; the second dies after two of its images
            for count, _ in enumerate(samples):
                if count == 1:
                    raise RuntimeError("simulated crash")
        written.append(shard)
        return real_write_shard(root, shard, samples, info)

    monkeypatch.setattr(job.dataset, "write_shard", crash_in_the_second_shard)
    with pytest.raises(RuntimeError, match="simulated crash"):
        render_dataset(_request(demo_scene, crashed, samples=12), bodies=body_model, show_progress=False)
    monkeypatch.setattr(job.dataset, "write_shard", real_write_shard)
    first = sorted(path.relative_to(crashed) for path in crashed.rglob("shard-*") if path.is_dir())
    assert [str(p) for p in first if not str(p).endswith(".partial")][:1] == [f"{plan_regions(demo_scene)[0].name}"
                                                                              "/shard-00000"]
    summary = render_dataset(_request(demo_scene, crashed, samples=12), bodies=body_model, show_progress=False)
    assert summary["skipped_shards"] == 1
    assert not list(crashed.rglob("*.partial"))
    assert _tree(crashed) == _tree(rendered_dataset)


def test_rerunning_a_finished_dataset_renders_nothing(rendered_dataset, demo_scene, body_model) -> None:
    before = {path: path.stat().st_mtime_ns for path in rendered_dataset.rglob("*.png")}
    summary = render_dataset(_request(demo_scene, rendered_dataset, samples=12), bodies=body_model,
                             show_progress=False)
    assert summary["rendered_now"] == {} and summary["skipped_shards"] == 6
    assert before == {path: path.stat().st_mtime_ns for path in rendered_dataset.rglob("*.png")}


def test_the_progress_bar_shows_unless_quiet(tmp_path, rendered_dataset, body_model, monkeypatch, capsys) -> None:
    """``vc-render --quiet`` (what ``vc-compile --quiet`` passes on) renders without a progress bar."""
    monkeypatch.setattr(job, "BodyModel", lambda: body_model)  # the CLI would build its own: a minute
    resumed = tmp_path / "resumed"
    shutil.copytree(rendered_dataset, resumed)
    last_shard = sorted(resumed.glob("*/shard-*"))[-1]
    arguments = [str(DEMO), "-o", str(resumed), "--samples", "12", "--spp", "4", "--shard-size", "5"]
    for quiet, bar_shown in ((False, True), (True, False)):
        shutil.rmtree(last_shard)
        capsys.readouterr()
        assert render_cli.main(arguments + (["--quiet"] if quiet else [])) == 0
        assert ("sample/s" in capsys.readouterr().err) == bar_shown
        assert _tree(resumed) == _tree(rendered_dataset)


def test_other_settings_in_the_same_folder_are_refused(rendered_dataset, capsys) -> None:
    status = render_cli.main([str(DEMO), "-o", str(rendered_dataset), "--samples", "12", "--spp", "2",
                              "--shard-size", "5"])
    assert status == EXIT_BAD_INPUT
    assert "different settings" in capsys.readouterr().err


def test_an_effect_that_is_off_or_unknown_to_an_older_render_does_not_refuse_it(rendered_dataset) -> None:
    from vc.render.dataset import check_manifest, read_manifest

    current = read_manifest(rendered_dataset)
    older = {**current, "effects": [effect for effect in current["effects"] if effect["on"]]}
    assert len(older["effects"]) < len(current["effects"])  # the demo has effects that are off
    check_manifest(rendered_dataset, older, current)  # the pixels depend on the effects that are on alone
    changed = [{**effect, "parameters": {**effect["parameters"], "changed": True}} if effect["on"] else effect
               for effect in current["effects"]]
    with pytest.raises(InputError, match="other camera effects"):
        check_manifest(rendered_dataset, {**current, "effects": changed}, current)


# --- bad input (no rendering happens: the checks come first) -------------------------------------------------
@pytest.mark.parametrize(("arguments", "message"), [
    (["--samples", "3", "--regions", "nowhere"], "unknown region nowhere"),
    (["--samples", "0"], "must be at least 1"),
    (["--samples", "2", "--spp", "-1"], "must be at least 1"),
    (["--samples", "2", "--processes", "0"], "must be at least 1"),
    (["--preview", "--processes", "2"], "a preview renders in this process"),
])
def test_bad_arguments_exit_with_status_2(tmp_path, capsys, arguments, message) -> None:
    try:
        status = render_cli.main([str(DEMO), "-o", str(tmp_path / "out"), *arguments])
    except SystemExit as exit_:  # argparse's own checks exit with status 2 too
        status = exit_.code
    assert status == EXIT_BAD_INPUT
    assert message in capsys.readouterr().err


def test_an_unwritable_output_folder_is_refused(tmp_path, capsys) -> None:
    blocker = tmp_path / "a-file"
    blocker.write_text("not a folder")
    assert render_cli.main([str(DEMO), "-o", str(blocker / "dataset"), "--samples", "2"]) == EXIT_BAD_INPUT
    assert "cannot create the output folder" in capsys.readouterr().err


def test_a_scene_without_walkable_area_in_view_is_refused(tmp_path, capsys) -> None:
    scene = base_scene()
    scene["layout"]["walkable"] = [[[-8.0, -40.0], [8.0, -40.0], [8.0, -30.0], [-8.0, -30.0]]]  # behind the camera
    path = write_scene(tmp_path, scene)
    assert render_cli.main([str(path), "-o", str(tmp_path / "out"), "--samples", "2"]) == EXIT_BAD_INPUT
    error = capsys.readouterr().err
    assert "layout.walkable" in error and str(path) in error
    assert not (tmp_path / "out").exists()


def test_a_dataset_of_an_unknown_format_is_refused_by_the_trainer(tmp_path):
    from vc.render.dataset import open_region

    (tmp_path / "manifest.json").write_text(json.dumps({"format_version": 99, "regions": {}}))
    with pytest.raises(InputError, match="unsupported dataset format 99"):
        open_region(tmp_path, "r0")
