"""A trained region network as an ONNX graph an appliance can run as is (docs/design.md, "Bundle").

The graph takes the region's crop of the frame exactly as the camera delivers it — uint8, (1, crop height,
crop width, 3), RGB — and does the rest itself: resize to the network input (bilinear, half-pixel centres, as
``cv2.INTER_LINEAR`` made the training backgrounds), scale to [0, 1], the network, and returns its heat maps
(1, C, h, w) in the layout of :mod:`vc.deploy.heatmaps`. Shapes are fixed (one region, one crop window), opset
17, the classic TorchScript exporter (no ``onnxscript`` needed); the network's config and the region travel as
metadata.

Given the run's scene, the bundle also carries the scene's background as scene fitness measures frames against it
(``reference/background.npz``, :class:`vc.deploy.fitness.SceneReference`): the background image every render was
composited on, reduced, with the scene's camera response. The render dataset keeps neither the image nor the scene's
path, so the scene is given (``vc-compile`` gives its own; ``vc-export --scene``), and it must be the scene the run
was trained for: its content hash, which covers the image, is the run's.
"""

from __future__ import annotations

import io
import json
import tempfile
import warnings
import zipfile
from dataclasses import asdict
from pathlib import Path

import numpy as np
import onnx
import onnxruntime as ort
import torch
import torch.nn.functional as F
from torch import Tensor, nn

from vc.calibration.camera import camera_from_dict
from vc.deploy.bundle import (
    BUNDLE_FORMAT,
    BUNDLE_FORMAT_VERSION,
    CROP_POSE,
    CROP_POSE_MEMBER,
    FACING,
    FACING_MEMBER,
    MANIFEST,
    MODELS,
    REFERENCE,
    REFERENCE_MEMBER,
    sha256,
)
from vc.deploy.crop_pose import CROP_SIZE as CROP_POSE_SIZE
from vc.deploy.crop_pose import MAP_STRIDE, MAPS_OUTPUT
from vc.deploy.decoder_file import DECODER_FILE, decoder_file
from vc.deploy.facing import ACROSS_OUTPUT, CROP_SIZE, FRAME_INPUT, HEAD_OUTPUT, ROIS_INPUT
from vc.deploy.facing import OUTPUT_NAME as FACING_OUTPUT
from vc.deploy.fitness import FitRange, SceneReference
from vc.deploy.heatmaps import channel_names
from vc.deploy.signing import SIGNATURE, sign_manifest
from vc.errors import InputError
from vc.io import atomic_directory, atomic_path, read_image
from vc.keypoints import COCO_KEYPOINTS, COCO_SKELETON_1BASED
from vc.model.camera_range import fit_range_of
from vc.model.codec import expected_height_map
from vc.model.crop_pose import CROP_POSE_MODEL, CROP_POSE_REPORT, CropPoseNet
from vc.model.facing import (
    CROPS,
    FACING_MODEL,
    FACING_OPSET,
    FACING_REPORT,
    FaceTurnNet,
    FacingNet,
    HeadColours,
    crop_graph,
)
from vc.model.network import ScenePoseNet
from vc.model.operators import graph_operators, outside_conservative_set
from vc.model.precision import choose_precision
from vc.model.trainer import Checkpoint, TrainConfig, load_checkpoint
from vc.render.camera_measurements import video_frames
from vc.render.dataset import RegionData, open_region
from vc.scenes.loader import Scene
from vc.versions import package_versions

OPSET = 17
INPUT_NAME, OUTPUT_NAME = "crop", "heatmaps"


class DeployedNetwork(nn.Module):
    """uint8 NHWC crop -> heat maps: the preprocessing an appliance would otherwise have to reimplement."""

    def __init__(self, net: ScenePoseNet, crop_size: tuple[int, int], input_size: tuple[int, int]) -> None:
        super().__init__()
        self.net, self.input_size = net.eval(), input_size
        self.resize = tuple(crop_size) != tuple(input_size)  # fixed per region: decided here, not while tracing

    def forward(self, crop: Tensor) -> Tensor:
        image = crop.permute(0, 3, 1, 2).float()
        if self.resize:
            width, height = self.input_size
            image = F.interpolate(image, size=(height, width), mode="bilinear", align_corners=False, antialias=False)
        return self.net(image / 255.0)["heatmaps"]


def export_onnx(net: ScenePoseNet, crop_size: tuple[int, int], input_size: tuple[int, int],
                metadata: dict[str, object]) -> bytes:
    """The serialised ONNX model of ``net`` for crops of ``crop_size`` (width, height)."""
    wrapper = DeployedNetwork(net, crop_size, input_size)
    example = torch.zeros(1, crop_size[1], crop_size[0], 3, dtype=torch.uint8)
    buffer = io.BytesIO()
    with torch.no_grad(), warnings.catch_warnings():
        warnings.simplefilter("ignore", DeprecationWarning)  # the classic exporter announces its own retirement
        torch.onnx.export(wrapper, (example,), buffer, input_names=[INPUT_NAME], output_names=[OUTPUT_NAME],
                          opset_version=OPSET, dynamo=False, do_constant_folding=True)
    model = folded(onnx.load_from_string(buffer.getvalue()))
    for key, value in metadata.items():
        entry = model.metadata_props.add()
        entry.key, entry.value = key, value if isinstance(value, str) else json.dumps(value)
    onnx.checker.check_model(model)
    return model.SerializeToString()


class _FacingReaders(nn.Module):
    """The facing networks side by side on the same crops, for one export: the classifier, then those of the face
    turn and the head's colours that are given."""

    def __init__(self, facing: FacingNet, turn: FaceTurnNet | None, head: HeadColours | None) -> None:
        super().__init__()
        self.readers = nn.ModuleList([reader for reader in (facing, turn, head) if reader is not None])

    def forward(self, crops: torch.Tensor) -> tuple[torch.Tensor, ...]:
        return tuple(reader(crops) for reader in self.readers)


def export_facing(net: FacingNet, turn: FaceTurnNet | None = None, head: HeadColours | None = None) -> bytes:
    """The facing model as a bundle ships it (:mod:`vc.model.facing` step 5): :func:`crop_graph` feeding ``net``
    (and ``turn`` and ``head`` where given), the frame (1, H, W, 3) uint8 and the crops' rectangles (N, 4) in, a
    front logit per person (N,) out (and where each face points, (N,), and the head's front logit, (N,))."""
    outputs = [FACING_OUTPUT] + [name for name, reader in ((ACROSS_OUTPUT, turn), (HEAD_OUTPUT, head))
                                 if reader is not None]
    module: nn.Module = net if len(outputs) == 1 else _FacingReaders(net, turn, head)
    return _reading_crops(module, CROP_SIZE, outputs)


def export_crop_pose(net: CropPoseNet) -> bytes:
    """The keypoint model as a bundle ships it (:mod:`vc.model.crop_pose` step 4): :func:`crop_graph` at the model's
    crop size feeding ``net``, the frame (1, H, W, 3) uint8 and the crops' rectangles (N, 4) in, the heat maps (N,
    17, 48, 24) out."""
    return _reading_crops(net, CROP_POSE_SIZE, [MAPS_OUTPUT])


def _reading_crops(module: nn.Module, size: tuple[int, int], outputs: list[str]) -> bytes:
    """One ONNX graph of :func:`crop_graph` at ``size`` (width, height) feeding ``module``, whose ``outputs`` each
    hold one row per person."""
    module.eval()
    buffer = io.BytesIO()
    example = torch.zeros(1, 3, size[1], size[0])
    with torch.no_grad(), warnings.catch_warnings():
        warnings.simplefilter("ignore", DeprecationWarning)  # the classic exporter announces its own retirement
        torch.onnx.export(module, (example,), buffer, input_names=[CROPS], output_names=outputs,
                          dynamic_axes={CROPS: {0: "people"}, **{name: {0: "people"} for name in outputs}},
                          opset_version=FACING_OPSET, dynamo=False, do_constant_folding=True)
    network = onnx.load_from_string(buffer.getvalue())
    crops = crop_graph(size)
    crops.ir_version = network.ir_version  # merged graphs share one IR version: the exporter's
    model = onnx.compose.merge_models(crops, network, io_map=[(CROPS, CROPS)])
    versions = {entry.domain: entry.version for entry in model.opset_import}  # both name the default domain
    del model.opset_import[:]
    model.opset_import.extend(onnx.helper.make_opsetid(domain, version) for domain, version in versions.items())
    onnx.checker.check_model(model)
    return model.SerializeToString()


def folded(model: onnx.ModelProto) -> onnx.ModelProto:
    """``model`` with what its fixed shapes make constant computed once: the tracer leaves the resize's target size
    as shape arithmetic (Shape, Slice, Concat) that an NPU compiler refuses (:mod:`vc.model.operators`). onnxruntime's
    basic, ONNX-only optimisations fold it (the same the int8 quantizer's preprocessing runs, so int8 graphs come
    out as before); the opset imports they add for their own domains, unused, are dropped."""
    with tempfile.TemporaryDirectory(prefix="vc-fold-") as folder:
        options = ort.SessionOptions()
        options.graph_optimization_level = ort.GraphOptimizationLevel.ORT_ENABLE_BASIC
        options.optimized_model_filepath = str(Path(folder) / "folded.onnx")
        ort.InferenceSession(model.SerializeToString(), options, providers=["CPUExecutionProvider"])
        result = onnx.load(options.optimized_model_filepath)
    used = {node.domain for node in result.graph.node} | {""}
    kept = [entry for entry in result.opset_import if entry.domain in used]
    del result.opset_import[:]
    result.opset_import.extend(kept)
    return result


def _npy_bytes(array: np.ndarray) -> bytes:
    buffer = io.BytesIO()
    np.save(buffer, array, allow_pickle=False)
    return buffer.getvalue()


def _finished_checkpoints(run: Path) -> list[Checkpoint]:
    paths = sorted((run / "checkpoints").glob("*.pt"))
    if not paths:
        raise InputError(run, "checkpoints", "no checkpoints in this run folder (train it with vc-train first)")
    checkpoints = [load_checkpoint(path) for path in paths]
    for checkpoint in checkpoints:
        content = checkpoint.content
        if checkpoint.step < checkpoint.config.steps:
            raise InputError(checkpoint.path, "step", f"training of region {content['region']!r} is not finished "
                                                      f"(step {checkpoint.step} of {checkpoint.config.steps};"
                                                      f" run vc-train again to resume it)")
        if content["scene_hash"] != checkpoints[0].content["scene_hash"]:
            raise InputError(checkpoint.path, "scene_hash", f"region {content['region']!r} was trained for another "
                                                            f"scene than {checkpoints[0].path.name}")
        if not content.get("scene_camera"):
            raise InputError(checkpoint.path, "scene_camera", "the dataset it was trained on predates bundle export "
                                                              "(no full-frame camera); render and train it again")
    return checkpoints


def network_from_checkpoint(checkpoint: Checkpoint) -> ScenePoseNet:
    net = ScenePoseNet(checkpoint.config.network)
    net.load_state_dict(checkpoint.content["model"])
    return net.eval()


def _evenly_spaced(samples: list, count: int) -> list:
    """``count`` samples spread over the whole list (shards differ: one per stretch of the dataset)."""
    if count >= len(samples):
        return list(samples)
    return [samples[int(i)] for i in np.linspace(0, len(samples) - 1, count).round()]


def _region_data(checkpoint: Checkpoint, config: TrainConfig) -> RegionData:
    dataset = checkpoint.dataset
    try:
        return open_region(dataset, checkpoint.content["region"], config.held_out_fraction)
    except InputError as error:
        raise InputError(checkpoint.path, "dataset", f"measuring or calibrating precisions needs the dataset the "
                                                     f"region was trained on, {dataset}: {error}") from None


def scene_reference(scene: Scene) -> SceneReference:
    """The scene fitness reference of ``scene``: its background image through its camera response."""
    decode = scene.camera_response().response.decode(np.arange(256, dtype=np.uint8))
    return SceneReference.of_background(read_image(scene.image_path), decode)


def with_reference(manifest: dict, files: dict[str, bytes], reference: SceneReference,
                   made_from: str, fit_range: FitRange | None = None) -> tuple[dict, dict[str, bytes]]:
    """The bundle ``manifest`` and ``files`` with ``reference`` added as :data:`~vc.deploy.bundle.REFERENCE_MEMBER`
    (``made_from`` says from what, for people reading the manifest), and how far a fit frame may depart from it
    (``fit_range``; None: the background's one look)."""
    data = reference.to_bytes()
    height, width = reference.cells.shape[:2]
    entry = {"background": REFERENCE_MEMBER, "background_sha256": sha256(data), "made_from": made_from,
             "cells": [width, height], "cell_px": reference.cell_px,
             **({} if fit_range is None else {"fit_range": fit_range.to_dict()})}
    return {**manifest, REFERENCE: entry}, {**files, REFERENCE_MEMBER: data}


def bundle_files(run: Path, precision: str = "fp32", eval_samples: int = 200, calibration_samples: int = 64,
                 show_progress: bool = False, scene: Scene | None = None) -> tuple[dict, dict[str, bytes]]:
    """The manifest and the files (relative name -> bytes) of the bundle of a finished run.

    Every region is exported at fp32, converted to each precision and measured on up to ``eval_samples``
    held-out renders (0: no measurement; then only ``precision`` is built); the model kept is ``precision``'s
    (``auto``: per region, int8 where it holds, see :func:`vc.model.precision.auto_precision`). With ``scene``
    (the run's), the bundle carries its scene fitness reference (module docstring).
    """
    checkpoints = _finished_checkpoints(run)
    first = checkpoints[0].content
    if scene is not None and scene.content_hash != first["scene_hash"]:
        raise InputError(scene.path, "scene_hash", f"is not the scene run {run} was trained for (scene "
                                                   f"{first['scene']!r}, {first['scene_hash'][:12]}…; this one "
                                                   f"{scene.content_hash[:12]}…): its background would not be the "
                                                   f"renders'")
    first_config = checkpoints[0].config
    layouts = {checkpoint.content["region"]: checkpoint.config.network.heatmap_channels for checkpoint in checkpoints}
    if len(set(layouts.values())) > 1:  # the manifest names one output layout for every region
        raise InputError(run, "checkpoints", f"the regions emit different heat-map layouts ({layouts} maps: some "
                                             f"trained with centre offsets, some without); train them alike")
    files: dict[str, bytes] = {}
    regions = []
    for checkpoint in checkpoints:
        content, name = checkpoint.content, checkpoint.content["region"]
        config = checkpoint.config
        entry = content["region_entry"]
        crop_window = [int(v) for v in entry["crop_window"]]
        crop_size, input_size = (crop_window[2], crop_window[3]), tuple(int(v) for v in entry["input_size"])
        model_name, heights_name = f"{MODELS}/{name}.onnx", f"{MODELS}/{name}.heights.npy"
        fp32 = export_onnx(network_from_checkpoint(checkpoint), crop_size, input_size,
                           {"scene": content["scene"], "region": name, "network": config.network.to_dict()})
        heights = expected_height_map(camera_from_dict(entry["camera"]), config.codec.stride,
                                      content["reference_height_m"])
        needs_data = eval_samples > 0 or precision in ("int8", "auto")
        data = _region_data(checkpoint, config) if needs_data else None
        choice = choose_precision(
            fp32, precision, _evenly_spaced(data.train, calibration_samples) if data else [],
            _evenly_spaced(data.held_out, eval_samples) if data and eval_samples > 0 else [],
            crop_size, config.decode, heights, show_progress, name)
        files[model_name], files[heights_name] = choice.model, _npy_bytes(heights)
        regions.append({
            "name": name, "crop_window": crop_window, "input_size": list(input_size),
            "output_stride": config.codec.stride, "decode": asdict(config.decode),
            "ground_polygon": entry["ground_polygon"], "owned_image_area": entry["owned_image_area"],
            "reference_height_m": content["reference_height_m"], "network": config.network.to_dict(),
            "precision": choice.precision, "held_out_accuracy": choice.accuracy,
            "operators": dict(sorted(graph_operators(choice.model).items())),
            "operators_outside_conservative_set": outside_conservative_set(choice.model),
            "model": model_name, "model_sha256": sha256(files[model_name]),
            "expected_height": heights_name, "expected_height_sha256": sha256(files[heights_name]),
        })
    precisions = sorted({region["precision"] for region in regions})
    manifest = {
        "format": BUNDLE_FORMAT, "format_version": BUNDLE_FORMAT_VERSION, "scene": first["scene"],
        "scene_hash": first["scene_hash"], "camera": first["scene_camera"],
        "frame_size": first["scene_camera"]["size"],
        "precision": precisions[0] if len(precisions) == 1 else "mixed",
        "input": {"name": INPUT_NAME, "dtype": "uint8", "layout": "NHWC RGB, the region's crop window of the frame"},
        "output": {"name": OUTPUT_NAME, "channels": list(channel_names(first_config.network.heatmap_channels))},
        "keypoints": list(COCO_KEYPOINTS), "skeleton": [list(pair) for pair in COCO_SKELETON_1BASED],
        "regions": regions, "versions": package_versions(),
    }
    files[DECODER_FILE] = decoder_file(manifest, files)
    manifest = {**manifest, "decoder_file": DECODER_FILE, "decoder_file_sha256": sha256(files[DECODER_FILE])}
    if (run / FACING_MODEL).is_file():  # trained by vc-train (vc.model.facing)
        manifest, files = with_facing(manifest, files, run)
    if (run / CROP_POSE_MODEL).is_file():  # trained by vc-train (vc.model.crop_pose)
        manifest, files = with_crop_pose(manifest, files, run)
    if scene is not None:
        reference, background = scene_reference(scene), read_image(scene.image_path)
        frames = video_frames(scene) if scene.video_path is not None else []
        fit_range = fit_range_of(first_config.camera_range, reference, background, scene.camera_response().response,
                                 frames)
        manifest, files = with_reference(manifest, files, reference,
                                         f"{scene.image_path.name}, the background of scene {scene.name!r}",
                                         fit_range)
        manifest = with_zones(manifest, scene)
    return manifest, files


def with_facing(manifest: dict, files: dict[str, bytes], run: Path) -> tuple[dict, dict[str, bytes]]:
    """The bundle with the run's facing model (:mod:`vc.model.facing`), fp32: at int8 it reads PETS09's people no
    faster and some of them worse (docs/decisions/0043-the-keypoint-model-at-int8-reads-twice.md)."""
    model = (run / FACING_MODEL).read_bytes()
    report = json.loads((run / FACING_REPORT).read_text()) if (run / FACING_REPORT).is_file() else {}
    turn = report.get("face_turn")  # runs trained before decision 0038 read the facing alone
    head = report.get("head_colours")  # and before 0041, without the head's colours
    entry = {"model": FACING_MEMBER, "model_sha256": sha256(model), "crop_size": list(CROP_SIZE),
             "inputs": [FRAME_INPUT, ROIS_INPUT], "output": FACING_OUTPUT,
             "held_out_accuracy": report.get("held_out_accuracy"),
             **({"across_output": ACROSS_OUTPUT, "face_turn_held_out_error": turn.get("held_out_error")}
                if isinstance(turn, dict) and "held_out_error" in turn else {}),
             **({"head_output": HEAD_OUTPUT, "head_held_out_auc": head.get("held_out_auc")}
                if isinstance(head, dict) and "held_out_auc" in head else {})}
    return {**manifest, FACING: entry}, {**files, FACING_MEMBER: model}


def with_crop_pose(manifest: dict, files: dict[str, bytes], run: Path) -> tuple[dict, dict[str, bytes]]:
    """The bundle with the run's keypoint model (:mod:`vc.model.crop_pose`), at the precision its training chose
    (:mod:`vc.model.crop_precision`)."""
    model = (run / CROP_POSE_MODEL).read_bytes()
    report = json.loads((run / CROP_POSE_REPORT).read_text()) if (run / CROP_POSE_REPORT).is_file() else {}
    entry = {"model": CROP_POSE_MEMBER, "model_sha256": sha256(model), "crop_size": list(CROP_POSE_SIZE),
             "map_stride": MAP_STRIDE, "inputs": [FRAME_INPUT, ROIS_INPUT], "output": MAPS_OUTPUT,
             "pairs": "image order", "held_out_pckh": report.get("held_out_pckh"),
             "precision": report.get("precision", "fp32")}
    return {**manifest, CROP_POSE: entry}, {**files, CROP_POSE_MEMBER: model}


def with_zones(manifest: dict, scene: Scene) -> dict:
    """The bundle ``manifest`` with the scene's named zones (:mod:`vc.deploy.zones`), when it has any."""
    if not scene.zones:
        return manifest
    return {**manifest, "zones": [{"name": zone.name, "frame": zone.frame, "polygon": zone.polygon}
                                  for zone in scene.zones]}


def write_bundle(manifest: dict, files: dict[str, bytes], output: Path, as_zip: bool,
                 signing_key: Path | None = None) -> None:
    """Write the bundle folder (or zip) under a temporary name and rename it into place; with ``signing_key`` (a
    PEM Ed25519 private key), the manifest's signature too."""
    manifest_bytes = (json.dumps(manifest, indent=2) + "\n").encode()
    documents = {MANIFEST: manifest_bytes, **files}
    if signing_key is not None:
        documents[SIGNATURE] = sign_manifest(manifest_bytes, signing_key)
    if as_zip:
        with atomic_path(output) as temporary, zipfile.ZipFile(temporary, "w", zipfile.ZIP_DEFLATED) as archive:
            for name, data in documents.items():
                archive.writestr(name, data)
        return
    with atomic_directory(output) as staging:
        for name, data in documents.items():
            (staging / name).parent.mkdir(parents=True, exist_ok=True)
            (staging / name).write_bytes(data)
