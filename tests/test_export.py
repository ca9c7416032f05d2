"""vc-export and the runtime: parity between PyTorch and onnxruntime, the bundle's validation (hashes, files,
format), the runtime's isolation from torch and mitsuba, frame checks and region ownership."""

from __future__ import annotations

import hashlib
import json
import os
import shutil
import warnings
import zipfile
from dataclasses import replace
from pathlib import Path

import numpy as np
import onnx
import onnxruntime as ort
import pytest
import torch
from conftest import SMALL, rewrite_checkpoint
from dataset_factory import INPUT_SIZE, region_camera, sample, write_dataset

from vc.cli.export import main as vc_export
from vc.cli.run import main as vc_run
from vc.deploy.areas import ImageArea, in_area
from vc.deploy.bundle import load_bundle
from vc.deploy.decode import SETTLED_SWITCHES, DecodeConfig, decode
from vc.deploy.heatmaps import ANATOMICAL_CHANNELS, HEATMAP_CHANNELS, OFFSET_CHANNELS, channel_names
from vc.deploy.runtime import Runtime
from vc.errors import InputError
from vc.io import write_image
from vc.keypoints import COCO_KEYPOINTS
from vc.model.codec import CodecConfig
from vc.model.export import DeployedNetwork, bundle_files, export_onnx
from vc.model.network import ScenePoseNet
from vc.model.precision import auto_precision, crop_sized, to_fp16, to_int8
from vc.model.trainer import RegionTrainer, TrainConfig, load_checkpoint
from vc.render.dataset import open_region


def _trained_network(seed: int = 0) -> ScenePoseNet:
    """A network with non-trivial batch-norm statistics, so that parity is tested on more than zeros."""
    torch.manual_seed(seed)
    net = ScenePoseNet(SMALL)
    for module in net.modules():
        if isinstance(module, torch.nn.BatchNorm2d):
            module.running_mean.uniform_(-0.2, 0.2)
            module.running_var.uniform_(0.5, 2.0)
            module.weight.data.uniform_(0.5, 1.5)
    for output in [net.head[-1], *(unit.belief[-1] for unit in net.sb_units)]:
        torch.nn.init.normal_(output.weight, std=0.3)
    return net.eval()


@pytest.mark.parametrize(("crop", "input_size"), [((128, 64), (128, 64)), ((150, 70), (128, 64)),
                                                  ((96, 40), (128, 64))])
def test_onnxruntime_matches_pytorch(crop, input_size):
    net = _trained_network()
    model = export_onnx(net, crop, input_size, {"region": "r0"})
    session = ort.InferenceSession(model, providers=["CPUExecutionProvider"])
    frame = np.random.default_rng(1).integers(0, 256, (1, crop[1], crop[0], 3), dtype=np.uint8)
    exported = session.run(None, {"crop": frame})[0]
    with torch.no_grad():
        reference = DeployedNetwork(net, crop, input_size)(torch.from_numpy(frame)).numpy()
    assert exported.shape == reference.shape == (1, HEATMAP_CHANNELS, input_size[1] // 4, input_size[0] // 4)
    assert np.max(np.abs(exported - reference)) <= 1e-4
    # Random weights: decode the strongest tenth of the centre map so that there are people to compare.
    config = DecodeConfig(centre_threshold=float(np.quantile(reference[0, 0], 0.9)))
    people = decode(exported[0], config), decode(reference[0], config)
    assert len(people[0]) == len(people[1]) > 0
    for a, b in zip(*people, strict=True):
        assert np.allclose(a.box, b.box, atol=1e-3) and np.allclose(a.keypoints, b.keypoints, atol=1e-3)


def test_the_bundle_lists_every_file_with_its_hash(bundle):
    manifest = json.loads((bundle / "manifest.json").read_text())
    assert manifest["format_version"] == 1 and manifest["frame_size"] == list(INPUT_SIZE)
    assert len(manifest["keypoints"]) == 17 and len(manifest["skeleton"]) == 19
    assert manifest["output"]["channels"] == list(channel_names()) and len(channel_names()) == HEATMAP_CHANNELS
    region = manifest["regions"][0]
    assert region["name"] == "r0" and region["crop_window"] == [0, 0, *INPUT_SIZE]
    assert {"onnx", "onnxruntime", "torch"} <= set(manifest["versions"])
    loaded = load_bundle(bundle)
    assert loaded.regions[0].expected_height_px.shape == (INPUT_SIZE[1] // 4, INPUT_SIZE[0] // 4)


def test_a_zip_bundle_loads_like_a_folder(trained_run, tmp_path):
    assert vc_export([str(trained_run), "-o", str(tmp_path / "bundle.zip"), "--zip"]) == 0
    assert zipfile.is_zipfile(tmp_path / "bundle.zip")
    assert load_bundle(tmp_path / "bundle.zip").regions[0].name == "r0"


@pytest.mark.parametrize(("damage", "message"), [
    (lambda b: (b / "models" / "r0.onnx").write_bytes((b / "models" / "r0.onnx").read_bytes() + b"x"), "SHA-256"),
    (lambda b: (b / "models" / "r0.onnx").unlink(), "models/r0.onnx is missing"),
    (lambda b: (b / "manifest.json").write_text(
        (b / "manifest.json").read_text().replace('"format_version": 1', '"format_version": 99')),
     "unsupported bundle format 99"),
    (lambda b: (b / "manifest.json").write_text("{"), "not valid JSON"),
    (lambda b: (b / "manifest.json").unlink(), "manifest.json is missing"),
])
def test_a_bad_bundle_is_refused_before_loading(bundle, tmp_path, damage, message):
    copy = Path(shutil.copytree(bundle, tmp_path / "copy"))
    damage(copy)
    with pytest.raises(InputError, match=message):
        load_bundle(copy)


@pytest.mark.parametrize("member", ["/etc/hostname", "../outside.onnx", "models/../../outside.onnx", "link.onnx"])
def test_a_bundle_member_outside_the_bundle_is_refused(bundle, tmp_path, member):
    copy = Path(shutil.copytree(bundle, tmp_path / "copy"))
    outside = tmp_path / "outside.onnx"
    outside.write_bytes((copy / "models" / "r0.onnx").read_bytes())
    (copy / "link.onnx").symlink_to(outside)
    manifest = json.loads((copy / "manifest.json").read_text())
    manifest["regions"][0]["model"] = member  # its hash still matches: only the name is hostile
    (copy / "manifest.json").write_text(json.dumps(manifest))
    with pytest.raises(InputError, match="not a path inside the bundle|leads outside the bundle"):
        load_bundle(copy)


def test_a_checkpoint_holding_code_is_refused_unrun(trained_run, tmp_path, capsys):
    run = Path(shutil.copytree(trained_run, tmp_path / "run"))
    checkpoint = torch.load(run / "checkpoints" / "r0.pt", weights_only=True)
    marker = tmp_path / "ran"
    checkpoint["history"] = _RunsCode(f"touch {marker}")
    torch.save(checkpoint, run / "checkpoints" / "r0.pt")
    assert vc_export([str(run), "-o", str(tmp_path / "bundle"), "--eval-samples", "0"]) == 2
    assert "refused: it holds a Python object" in capsys.readouterr().err
    assert not marker.exists() and not (tmp_path / "bundle").exists()


class _RunsCode:
    """What a hostile checkpoint holds: unpickling it runs a shell command."""

    def __init__(self, command: str) -> None:
        self.command = command

    def __reduce__(self):
        return os.system, (self.command,)


def test_a_corrupted_zip_is_refused(trained_run, tmp_path):
    path = tmp_path / "bundle.zip"
    assert vc_export([str(trained_run), "-o", str(path), "--zip"]) == 0
    data = bytearray(path.read_bytes())
    data[len(data) // 3] ^= 0xFF
    path.write_bytes(bytes(data))
    with pytest.raises(InputError, match="bundle.zip"):
        load_bundle(path)


def test_the_runtime_checks_frames(bundle):
    runtime = Runtime(bundle, threads=1)
    frame = sample(region_camera(), 0).image
    assert isinstance(runtime(frame), list)
    with pytest.raises(InputError, match="expected shape"):
        runtime(frame[:-1])
    with pytest.raises(InputError, match="uint8"):
        runtime(frame.astype(np.float32))


def test_ownership_follows_the_owned_area_with_holes():
    area = {"type": "Polygon", "coordinates": [[[0, 0], [10, 0], [10, 10], [0, 10], [0, 0]],
                                               [[4, 4], [6, 4], [6, 6], [4, 6], [4, 4]]]}
    points = np.array([[1, 1], [5, 5], [11, 5], [9.9, 9.9]])
    assert in_area(points, area).tolist() == [True, False, False, True]
    multi = {"type": "MultiPolygon", "coordinates": [area["coordinates"], [[[20, 0], [30, 0], [30, 5], [20, 0]]]]}
    assert in_area(np.array([[25, 1], [25, 4]]), multi).tolist() == [True, False]


def test_an_area_tested_in_one_pass_agrees_with_shapely_on_an_owned_area_with_many_holes():
    """The runtime tests all of a polygon's rings at once (outer ring and holes: :mod:`vc.deploy.areas`); an owned
    area with an obstacle hole beside another, and a second polygon, against shapely's own test."""
    import shapely

    outer = shapely.Polygon([(0, 0), (300, 10), (280, 200), (120, 260), (5, 180)])
    holes = [shapely.Point(x, y).buffer(r) for x, y, r in ((60, 60, 20), (110, 62, 25), (200, 120, 30),
                                                             (150, 190, 12))]
    area = shapely.MultiPolygon([outer.difference(shapely.union_all(holes)),
                                 shapely.box(400, 0, 450, 90)])
    geojson = shapely.geometry.mapping(area)
    points = np.random.default_rng(5).uniform([-20, -20], [470, 280], (4000, 2))
    expected = shapely.contains_xy(area, points[:, 0], points[:, 1])
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # the box's horizontal edges divide by nothing: no warning every frame
        assert ImageArea(geojson).contains(points).tolist() == expected.tolist()
    assert expected.sum() > 1000 and (~expected).sum() > 1000  # both sides well represented


def test_an_unfinished_run_is_not_exported(tmp_path, capsys):
    data_root = write_dataset(tmp_path / "dataset")
    config = TrainConfig(network=SMALL, steps=4, batch_size=2, warmup_steps=1, checkpoint_every=2)
    RegionTrainer(open_region(data_root, "r0"), config, tmp_path / "run", data_root, workers=0,
                  show_progress=False).train(until=2)
    assert vc_export([str(tmp_path / "run"), "-o", str(tmp_path / "bundle")]) == 2
    assert "not finished (step 2 of 4" in capsys.readouterr().err
    assert not (tmp_path / "bundle").exists()


def test_bundle_files_refuse_an_empty_run(tmp_path):
    with pytest.raises(InputError, match="no checkpoints"):
        bundle_files(tmp_path)


def _heatmaps(model: bytes, crops: np.ndarray) -> np.ndarray:
    session = ort.InferenceSession(model, providers=["CPUExecutionProvider"])
    return np.concatenate([session.run(None, {"crop": crop[None]})[0] for crop in crops])


def test_int8_and_fp16_models_stay_close_to_fp32(tmp_path):
    data = open_region(write_dataset(tmp_path / "dataset"), "r0")
    model = export_onnx(_trained_network(), INPUT_SIZE, INPUT_SIZE, {})
    crops = np.stack([sample(region_camera(), index, seed=7).image for index in range(3)])
    reference = _heatmaps(model, crops)
    int8 = to_int8(model, data.train[:8], INPUT_SIZE)
    int8_ops = {node.op_type for node in onnx.load_from_string(int8).graph.node}
    assert "QuantizeLinear" in int8_ops
    assert "Relu" not in int8_ops  # each folded into its quantized convolution, not rectified in float between them
    fp16 = to_fp16(model)
    assert any(init.data_type == onnx.TensorProto.FLOAT16 for init in onnx.load_from_string(fp16).graph.initializer)
    spread = reference.max() - reference.min()
    assert np.abs(_heatmaps(fp16, crops) - reference).max() <= 2e-3 * spread
    assert np.abs(_heatmaps(int8, crops) - reference).mean() <= 0.05 * spread


def _first_codes(model: bytes, crop: np.ndarray) -> np.ndarray:
    """The codes the int8 graph's first quantizer hands the first convolution, for one crop."""
    graph = onnx.load_from_string(model)
    codes = next(node for node in graph.graph.node if node.op_type == "QuantizeLinear").output[0]
    graph.graph.output.append(onnx.helper.make_tensor_value_info(codes, onnx.TensorProto.UINT8, None))
    session = ort.InferenceSession(graph.SerializeToString(), providers=["CPUExecutionProvider"])
    return session.run([codes], {"crop": crop[None]})[0][0]


@pytest.mark.parametrize("crop_size", [INPUT_SIZE, (160, 80)])  # as the network input; resized in the graph
def test_int8_quantizes_the_pixels_themselves(tmp_path, crop_size):
    data = open_region(write_dataset(tmp_path / "dataset"), "r0")
    net = _trained_network()
    model = export_onnx(net, crop_size, INPUT_SIZE, {})
    int8 = to_int8(model, data.train[:8], crop_size)
    first_ops = []
    for node in onnx.load_from_string(int8).graph.node:
        if node.op_type == "QuantizeLinear":
            break
        if node.op_type != "DequantizeLinear":
            first_ops.append(node.op_type)
    # no float normalisation over the input: the pixels (resized where the crop is not the input's size) go in
    assert first_ops == ["Transpose", "Cast"] + (["Resize"] if crop_size != INPUT_SIZE else [])
    if crop_size == INPUT_SIZE:
        # every 8-bit level reaches the network as itself (the normalised input's quantizer made odd levels even)
        levels = np.repeat(np.arange(256, dtype=np.uint8), crop_size[0] * crop_size[1] * 3 // 256 + 1)
        crop = levels[:crop_size[0] * crop_size[1] * 3].reshape(crop_size[1], crop_size[0], 3)
        np.testing.assert_array_equal(_first_codes(int8, crop), crop.transpose(2, 0, 1))
    # and the network's maps stay those of fp32 (the half-level offset of code 128 moved into the first bias)
    crops = np.stack([crop_sized(sample(region_camera(), index, seed=7).image, crop_size) for index in range(3)])
    reference = _heatmaps(model, crops)
    assert np.abs(_heatmaps(int8, crops) - reference).mean() <= 0.05 * (reference.max() - reference.min())


def test_auto_keeps_int8_only_where_it_holds():
    fp32 = {"ap50": 0.95, "pckh": 0.80}
    assert auto_precision({"fp32": fp32, "int8": {"ap50": 0.945, "pckh": 0.79}}) == "int8"
    assert auto_precision({"fp32": fp32, "int8": {"ap50": 0.93, "pckh": 0.80}}) == "fp32"
    assert auto_precision({"fp32": fp32, "int8": {"ap50": 0.95, "pckh": 0.70}}) == "fp32"


def test_an_int8_bundle_records_every_precision_and_runs(trained_run, tmp_path):
    output = tmp_path / "bundle"
    assert vc_export([str(trained_run), "-o", str(output), "--precision", "int8", "--eval-samples", "8",
                      "--calibration-samples", "4", "--quiet"]) == 0
    manifest = json.loads((output / "manifest.json").read_text())
    region = manifest["regions"][0]
    assert manifest["precision"] == region["precision"] == "int8"
    assert set(region["held_out_accuracy"]) == {"fp32", "fp16", "int8"}
    assert region["held_out_accuracy"]["int8"]["ground_truth"] > 0
    runtime = Runtime(output, threads=1)
    assert runtime.runners[0].entry.precision == "int8"
    assert isinstance(runtime(sample(region_camera(), 0).image), list)


def test_int8_without_the_training_dataset_is_refused(trained_run, tmp_path, capsys):
    run = Path(shutil.copytree(trained_run, tmp_path / "run"))
    rewrite_checkpoint(run / "checkpoints" / "r0.pt", lambda content: content.update(dataset=str(tmp_path / "moved")))
    assert vc_export([str(run), "-o", str(tmp_path / "bundle"), "--precision", "int8"]) == 2
    assert "needs the dataset the region was trained on" in capsys.readouterr().err
    assert not (tmp_path / "bundle").exists()


def test_auto_precision_without_held_out_renders_is_one_line_naming_the_field(trained_run, tmp_path, capsys):
    assert vc_export([str(trained_run), "-o", str(tmp_path / "bundle"), "--precision", "auto",
                      "--eval-samples", "0"]) == 2
    error = capsys.readouterr().err.strip()
    assert error.count("\n") == 0 and "export.eval_samples" in error and "precision auto" in error
    assert not (tmp_path / "bundle").exists()


def test_export_into_an_impossible_folder_is_an_input_error(trained_run, tmp_path, capsys):
    (tmp_path / "file").write_text("")
    assert vc_export([str(trained_run), "-o", str(tmp_path / "file" / "bundle"), "--eval-samples", "0"]) == 2
    assert "cannot create output folder" in capsys.readouterr().err


def test_masks_map_cells_to_the_frame_pixels_they_cover(bundle):
    runner = Runtime(bundle, threads=1).runners[0]
    stride = runner.entry.decode.stride
    cells = np.zeros((INPUT_SIZE[1] // stride, INPUT_SIZE[0] // stride), bool)
    cells[3:9, 10:14] = True
    cells[5, 20] = True
    mask, (x0, y0) = runner._frame_mask(cells)
    frame = np.zeros((INPUT_SIZE[1], INPUT_SIZE[0]), bool)
    frame[y0:y0 + mask.shape[0], x0:x0 + mask.shape[1]] = mask
    rows, columns = np.indices(frame.shape)
    cell_of_pixel = cells[np.minimum(rows // stride, cells.shape[0] - 1), np.minimum(columns // stride,
                                                                                     cells.shape[1] - 1)]
    assert np.array_equal(frame, cell_of_pixel) and mask.shape == (6 * stride, 11 * stride)


def _key_pair(folder: Path) -> tuple[Path, Path]:
    from cryptography.hazmat.primitives import serialization
    from cryptography.hazmat.primitives.asymmetric import ed25519

    key = ed25519.Ed25519PrivateKey.generate()
    private, public = folder / "key.pem", folder / "key.pub"
    private.write_bytes(key.private_bytes(serialization.Encoding.PEM, serialization.PrivateFormat.PKCS8,
                                          serialization.NoEncryption()))
    public.write_bytes(key.public_key().public_bytes(serialization.Encoding.PEM,
                                                     serialization.PublicFormat.SubjectPublicKeyInfo))
    return private, public


def test_a_signed_bundle_refuses_a_manifest_rewritten_with_matching_hashes(trained_run, tmp_path, capsys):
    private, public = _key_pair(tmp_path)
    signed = tmp_path / "signed"
    assert vc_export([str(trained_run), "-o", str(signed), "--eval-samples", "0", "--sign", str(private)]) == 0
    assert Runtime(signed, threads=1, public_key=public).bundle.regions  # signed by the key's owner: runs
    # An attacker swaps a model and rewrites its hash in the manifest: the hashes agree, the signature does not.
    forged = Path(shutil.copytree(signed, tmp_path / "forged"))
    model = forged / "models" / "r0.onnx"
    model.write_bytes(model.read_bytes() + b"\0")
    manifest = json.loads((forged / "manifest.json").read_text())
    manifest["regions"][0]["model_sha256"] = hashlib.sha256(model.read_bytes()).hexdigest()
    (forged / "manifest.json").write_text(json.dumps(manifest, indent=2) + "\n")
    assert load_bundle(forged).regions  # without a key, the hashes check out
    with pytest.raises(InputError, match="signature does not match"):
        load_bundle(forged, public_key=public)
    # Unsigned, or signed by another key: refused too; vc-run says so in one line, status 2.
    (tmp_path / "other").mkdir()
    _, stranger = _key_pair(tmp_path / "other")
    with pytest.raises(InputError, match="signature does not match"):
        load_bundle(signed, public_key=stranger)
    (forged / "manifest.sig").unlink()
    frame = tmp_path / "frame.png"
    write_image(frame, sample(region_camera(), 0).image)
    assert vc_run([str(forged), str(frame), "-o", str(tmp_path / "run"), "--public-key", str(public)]) == 2
    assert "not signed" in capsys.readouterr().err and not (tmp_path / "run").exists()


def test_a_run_moved_with_its_renders_still_exports(trained_run, tmp_path):
    moved = tmp_path / "elsewhere"
    shutil.copytree(trained_run.parent / "dataset", moved / "dataset")
    run = Path(shutil.copytree(trained_run, moved / "run"))
    checkpoint = torch.load(run / "checkpoints" / "r0.pt", weights_only=True)
    assert not Path(checkpoint["dataset"]).is_absolute()  # relative to the run folder
    # The original renders are not where the moved run looks: it reads its own copy.
    assert load_checkpoint(run / "checkpoints" / "r0.pt").dataset == (moved / "dataset").resolve()
    assert vc_export([str(run), "-o", str(tmp_path / "bundle"), "--precision", "int8", "--eval-samples", "4",
                      "--calibration-samples", "2"]) == 0


def test_regions_in_parallel_find_the_people_they_find_in_turn(bundle):
    """Regions run in a thread pool (the default with several regions and cores) must report the people they
    report one after the other, in the same order. Three regions share the test network, each owning a band of the
    frame; every centre peak is a person (the briefly trained network's centre map stays below 0.005), so there are
    people to compare."""
    loaded = load_bundle(bundle)
    entry = loaded.regions[0]
    width, height = loaded.frame_size
    bands = np.linspace(0, height, 4)

    def band(top: float, bottom: float) -> dict:
        return {"type": "Polygon", "coordinates": [[[0, top], [width, top], [width, bottom], [0, bottom], [0, top]]]}

    regions = [replace(entry, name=f"r{index}", owned_image_area=band(bands[index], bands[index + 1]),
                       decode=replace(entry.decode, centre_threshold=0.0))
               for index in range(3)]
    three = replace(loaded, regions=regions)
    frames = [sample(region_camera(), index).image for index in range(3)]
    with Runtime(three, threads=2, parallel_regions=True) as parallel, \
            Runtime(three, threads=2, parallel_regions=False) as in_turn:
        for frame in frames:
            found = [(person.region, person.score, person.box.tolist()) for person in parallel(frame)]
            assert found == [(person.region, person.score, person.box.tolist()) for person in in_turn(frame)]
            assert len({region for region, _, _ in found}) >= 2  # people from several regions, merged in one order


def test_a_closed_runtime_has_shut_its_threads_and_runs_no_frame(bundle):
    with Runtime(bundle, threads=2, parallel_regions=True) as runtime:
        pool = runtime.pool
        assert isinstance(runtime(sample(region_camera(), 0).image), list)
    assert pool._shutdown and runtime.pool is None
    with pytest.raises(RuntimeError, match="closed"):
        runtime(sample(region_camera(), 0).image)


def test_a_checkpoint_written_before_the_rule_still_loads(trained_run, tmp_path):
    from torch.torch_version import TorchVersion

    checkpoint = torch.load(trained_run / "checkpoints" / "r0.pt", weights_only=True)
    checkpoint.pop("content_sha256")  # what checkpoints held before: format 1, no digest, torch's version object
    checkpoint.update(format_version=1, versions={"torch": TorchVersion(torch.__version__)})
    torch.save(checkpoint, tmp_path / "old.pt")
    assert load_checkpoint(tmp_path / "old.pt").step == checkpoint["step"]


def test_a_network_with_centre_offsets_exports_names_its_maps_and_runs(tmp_path):
    data_root = write_dataset(tmp_path / "dataset")
    config = TrainConfig(network=SMALL, steps=2, batch_size=2, warmup_steps=1,
                         codec=CodecConfig(centre_offsets=True))
    RegionTrainer(open_region(data_root, "r0"), config, tmp_path / "run", data_root, workers=0,
                  show_progress=False).train()
    assert vc_export([str(tmp_path / "run"), "-o", str(tmp_path / "bundle"), "--quiet"]) == 0
    manifest = json.loads((tmp_path / "bundle" / "manifest.json").read_text())
    assert manifest["output"]["channels"] == list(channel_names(OFFSET_CHANNELS))
    assert manifest["output"]["channels"][-2:] == ["centre_offset_x", "centre_offset_y"]
    runtime = Runtime(tmp_path / "bundle", threads=1)
    frame = sample(region_camera(), 0).image
    assert runtime.runners[0].heatmaps(frame).shape[0] == OFFSET_CHANNELS
    assert isinstance(runtime(frame), list)


def _rewritten_manifest(bundle: Path, copy: Path, edit) -> Path:
    """A copy of ``bundle`` whose manifest ``edit`` changed (what a bundle another version exported holds)."""
    copy = Path(shutil.copytree(bundle, copy))
    manifest = json.loads((copy / "manifest.json").read_text())
    edit(manifest)
    (copy / "manifest.json").write_text(json.dumps(manifest, indent=2) + "\n")
    return copy


def test_a_bundle_naming_the_settled_switches_decodes_the_same_people(bundle, tmp_path):
    """A bundle exported while the decoder still had its settled switches names them at their settled values: it
    loads, and decodes exactly the people this version's export does (docs/decisions/0003-decoder-settings.md)."""
    manifest = json.loads((bundle / "manifest.json").read_text())
    assert not set(SETTLED_SWITCHES) & set(manifest["regions"][0]["decode"])  # this version's export names none
    older = _rewritten_manifest(bundle, tmp_path / "older",
                                lambda manifest: manifest["regions"][0]["decode"].update(SETTLED_SWITCHES))
    assert load_bundle(older).regions[0].decode == load_bundle(bundle).regions[0].decode
    frames = [sample(region_camera(), index).image for index in range(2)]
    with Runtime(bundle, threads=1) as current, Runtime(older, threads=1) as before:
        for frame in frames:
            heatmaps = current.runners[0].heatmaps(frame)
            np.testing.assert_array_equal(heatmaps, before.runners[0].heatmaps(frame))
            everyone = replace(current.runners[0].entry.decode, centre_threshold=0.0)  # people to compare
            found = [(person.score, person.box.tolist(), person.keypoints.tolist())
                     for person in current.runners[0].people_in(heatmaps, everyone)]
            assert found and found == [(person.score, person.box.tolist(), person.keypoints.tolist())
                                       for person in before.runners[0].people_in(
                                           heatmaps, replace(before.runners[0].entry.decode, centre_threshold=0.0))]


@pytest.mark.parametrize("name", sorted(SETTLED_SWITCHES))
def test_a_bundle_exported_with_a_retired_decoding_is_refused_by_name(bundle, tmp_path, capsys, name):
    other = not SETTLED_SWITCHES[name]
    refused = _rewritten_manifest(bundle, tmp_path / "refused",
                                  lambda manifest: manifest["regions"][0]["decode"].update({name: other}))
    with pytest.raises(InputError, match=f"regions.0.decode.{name}: exported with {name}={str(other).lower()}, a "
                                         f"decoding this version no longer has") as error:
        load_bundle(refused)
    assert error.value.path == str(refused) and "vc-export" in error.value.reason
    frame = tmp_path / "frame.png"
    write_image(frame, sample(region_camera(), 0).image)
    assert vc_run([str(refused), str(frame), "-o", str(tmp_path / "run")]) == 2
    assert f"decode.{name}" in capsys.readouterr().err and not (tmp_path / "run").exists()


def test_a_bundle_of_the_retired_19_map_layout_is_refused(bundle, tmp_path):
    refused = _rewritten_manifest(bundle, tmp_path / "refused", lambda manifest: manifest["output"].update(
        channels=["centre", *COCO_KEYPOINTS, "mask"]))
    assert ANATOMICAL_CHANNELS == 19
    with pytest.raises(InputError, match="output.channels: 19 heat maps, the layout of networks from before the "
                                         "handedness maps"):
        load_bundle(refused)


@pytest.mark.parametrize("name", sorted(SETTLED_SWITCHES))
def test_a_checkpoint_naming_a_settled_switch_loads_and_one_at_the_other_value_is_refused(trained_run, tmp_path,
                                                                                            name):
    settled, other = tmp_path / "settled.pt", tmp_path / "other.pt"
    for path, value in ((settled, SETTLED_SWITCHES[name]), (other, not SETTLED_SWITCHES[name])):
        shutil.copy(trained_run / "checkpoints" / "r0.pt", path)
        rewrite_checkpoint(path, lambda content, value=value: content["train_config"]["decode"].update({name: value}))
    assert load_checkpoint(settled).config == load_checkpoint(trained_run / "checkpoints" / "r0.pt").config
    with pytest.raises(InputError, match=f"train_config.decode.{name}: trained with {name}=") as error:
        load_checkpoint(other)
    assert error.value.path == str(other)


def test_a_checkpoint_of_the_retired_19_map_layout_is_refused(trained_run, tmp_path):
    path = tmp_path / "old.pt"
    shutil.copy(trained_run / "checkpoints" / "r0.pt", path)
    rewrite_checkpoint(path, lambda content: content["train_config"]["network"].pop("heatmap_channels"))
    with pytest.raises(InputError, match="train_config.network.heatmap_channels: trained with a network of 19 heat "
                                         "maps"):
        load_checkpoint(path)
