"""vc-eval: MOT ground truth, the baselines (HOG, a YOLO-pose style ONNX model) and the report on a small video."""

from __future__ import annotations

import json

import cv2
import numpy as np
import onnx
import pytest
from dataset_factory import INPUT_SIZE, region_camera, sample
from onnx import TensorProto, helper

from vc.cli.eval import main as vc_eval
from vc.deploy.boxes import box_iou
from vc.deploy.frames import FrameRange, FrameSource
from vc.errors import InputError
from vc.evaluation.baselines import HogPeopleDetector, YoloPoseOnnx, non_max_suppression
from vc.evaluation.mot import read_mot_boxes, read_mot_ids

TRUE_BOX = np.array([40.0, 10.0, 60.0, 50.0])  # x0, y0, x1, y1 in a 128x64 frame
YOLO_SIZE = 64


def _yolo_model(path) -> None:
    """A YOLO-pose style model (1, 56, N) that always reports TRUE_BOX (letterboxed into 64x64: scale 0.5, padded
    16 px at the top) with its keypoints at the box centre, a weaker near-duplicate of it and a box below the
    confidence floor."""
    scale, pad_y = 0.5, 16
    cx, cy = (TRUE_BOX[0] + TRUE_BOX[2]) / 2 * scale, (TRUE_BOX[1] + TRUE_BOX[3]) / 2 * scale + pad_y
    width, height = (TRUE_BOX[2] - TRUE_BOX[0]) * scale, (TRUE_BOX[3] - TRUE_BOX[1]) * scale
    rows = np.zeros((3, 56), np.float32)
    rows[0, :5] = cx, cy, width, height, 0.9
    rows[0, 5:] = np.tile([cx, cy, 0.9], 17)  # every keypoint at the box centre, confident
    rows[1, :5] = cx + 0.5, cy, width, height, 0.5
    rows[2, :5] = 5, 5, 4, 4, 0.0001
    constant = helper.make_tensor("rows", TensorProto.FLOAT, (1, 56, 3), rows.T.ravel())
    nodes = [helper.make_node("ReduceMean", ["images"], ["mean"], axes=[1, 2, 3], keepdims=0),
             helper.make_node("Mul", ["mean", "zero"], ["nothing"]),
             helper.make_node("Add", ["nothing", "rows"], ["output0"])]
    graph = helper.make_graph(nodes, "yolo-like", [helper.make_tensor_value_info(
        "images", TensorProto.FLOAT, (1, 3, YOLO_SIZE, YOLO_SIZE))],
        [helper.make_tensor_value_info("output0", TensorProto.FLOAT, (1, 56, 3))],
        initializer=[constant, helper.make_tensor("zero", TensorProto.FLOAT, (), [0.0])])
    onnx.save(helper.make_model(graph, opset_imports=[helper.make_opsetid("", 17)], ir_version=8), path)


def test_mot_boxes_are_read_per_frame_and_bad_lines_named(tmp_path):
    path = tmp_path / "gt.txt"
    path.write_text("1,9,499.2,157.7,31.0,75.2,1,-1,-1,-1\n1,15,258,218,33,89,1,-1,-1,-1\n3,9,10,20,5,10,1\n")
    boxes = read_mot_boxes(path)
    assert sorted(boxes) == [1, 3] and boxes[1].shape == (2, 4)
    assert np.allclose(boxes[1][0], [499.2, 157.7, 530.2, 232.9])
    ids = read_mot_ids(path)  # the person of each box, in the same order
    assert sorted(ids) == [1, 3] and ids[1].tolist() == [9, 15] and ids[3].tolist() == [9]
    path.write_text("1,9,499.2,157.7,31.0,75.2\n2,9,x,1,1,1\n")
    with pytest.raises(InputError, match="line 2"):
        read_mot_boxes(path)


def test_a_yolo_pose_model_is_letterboxed_and_suppressed(tmp_path):
    _yolo_model(tmp_path / "yolo.onnx")
    detector = YoloPoseOnnx(tmp_path / "yolo.onnx")
    boxes, scores, keypoints = detector(np.zeros((INPUT_SIZE[1], INPUT_SIZE[0], 3), np.uint8))
    assert detector.size == YOLO_SIZE and len(boxes) == 1
    assert np.allclose(boxes[0], TRUE_BOX, atol=1e-3) and scores[0] == pytest.approx(0.9)
    assert keypoints.shape == (1, 17, 3)  # mapped back to frame pixels like the boxes
    assert np.allclose(keypoints[0, :, :2], (TRUE_BOX[:2] + TRUE_BOX[2:]) / 2, atol=1e-3)
    # timed beside a bundle in one process, it must not spin-wait on the cores after its run
    assert detector.session.get_session_options().get_session_config_entry("session.intra_op.allow_spinning") == "0"


def test_non_max_suppression_keeps_the_best_of_each_overlap():
    boxes = np.array([[0, 0, 10, 10], [1, 0, 11, 10], [20, 20, 30, 30]], float)
    assert non_max_suppression(boxes, np.array([0.5, 0.9, 0.3]), 0.5).tolist() == [1, 2]


@pytest.mark.pets
def test_hog_finds_pets_people_with_boxes_shrunk_to_the_person(pets_data):
    frame = next(iter(FrameSource(pets_data / "vtest.avi", FrameRange(1, 1)))).image
    truth = read_mot_boxes(pets_data / "gt_dev_frames_0001-0400.txt")[1]
    boxes, scores, keypoints = HogPeopleDetector()(frame)
    assert keypoints is None
    assert len(boxes) == len(scores) > 0
    width, height = boxes[:, 2] - boxes[:, 0], boxes[:, 3] - boxes[:, 1]
    assert np.allclose(width / height, 32 / 96, rtol=0.05)  # 16 px off each side of the (rounded) 64x128 window
    assert (box_iou(truth, boxes).max(axis=1) >= 0.5).sum() >= len(truth) // 2


def _video_and_truth(tmp_path, frames: int = 4):
    writer = cv2.VideoWriter(str(tmp_path / "clip.avi"), cv2.VideoWriter_fourcc(*"MJPG"), 10, INPUT_SIZE)
    for index in range(frames):
        writer.write(np.ascontiguousarray(sample(region_camera(), index, seed=9).image[:, :, ::-1]))
    writer.release()
    x0, y0, x1, y1 = TRUE_BOX
    (tmp_path / "gt.txt").write_text("".join(f"{n},1,{x0},{y0},{x1 - x0},{y1 - y0},1,-1,-1,-1\n"
                                             for n in range(1, frames)))
    return tmp_path / "clip.avi", tmp_path / "gt.txt"


def test_vc_eval_scores_every_detector_and_draws_the_result(bundle, tmp_path):
    video, truth = _video_and_truth(tmp_path)
    _yolo_model(tmp_path / "yolo.onnx")
    output = tmp_path / "eval"
    assert vc_eval([str(bundle), "--video", str(video), "--gt", str(truth), "-o", str(output), "--threads", "1",
                    "--external", str(tmp_path / "yolo.onnx"), "--external-name", "yolo",
                    "--external", str(tmp_path / "yolo.onnx"), "--external-name", "yolo again", "--quiet"]) == 0
    metrics = json.loads((output / "metrics.json").read_text())
    assert metrics["frames"]["count"] == 3  # the annotated range, 1-3
    detectors = metrics["detectors"]
    assert set(detectors) == {"visual compiler", "visual compiler, each frame on its own", "HOG (OpenCV, real photos)",
                              "yolo", "yolo again"}
    assert detectors["yolo"]["ap50"] == 1.0 and detectors["yolo"]["ground_truth"] == 3
    assert all(0.0 <= d["ap50"] <= 1.0 and d["ms_per_frame"]["median"] > 0 for d in detectors.values())
    # Three annotated frames of one standing person span no area: scored in it, every detector scores the same.
    assert metrics["annotated_area"]["polygon"] is None
    assert all(d["ap50_in_annotated_area"] == d["ap50"] for d in detectors.values())
    # The video is tracked at its own rate, and the bundle is scored with and without tracking.
    assert metrics["tracking"]["fps"] == 10 and metrics["tracking"]["config"]["window_s"] > 0
    # The one person stands there from the first frame: nobody comes into view.
    assert metrics["arrivals"]["people"] == [] and metrics["arrivals"]["summary"]["walking in at an edge"] == {
        "people": 0, "found_in_first_frame": 0, "never_found": 0, "median_delay_frames": None,
        "found_within": {"seconds": 1.0, "people": 0}, "median_delay_s": None}
    # The bundle's pose and the second model's against the first: a model agrees with itself everywhere.
    agreement = metrics["pose_agreement"]
    assert agreement["reference"] == "yolo" and set(agreement["agreement"]) == {
        "visual compiler", "visual compiler, each frame on its own", "yolo again"}
    assert agreement["agreement"]["yolo again"]["overall"] == 1.0
    assert agreement["agreement"]["yolo again"]["people"] == 3
    for name in ("precision_recall.png", "contact_sheet.png", "detections.jsonl", "pose_agreement.png"):
        assert (output / name).stat().st_size > 0


def test_vc_eval_tracks_over_every_frame_of_the_span_and_scores_the_selected(bundle, tmp_path):
    video, truth = _video_and_truth(tmp_path, frames=6)
    tracked, alone = tmp_path / "tracked", tmp_path / "alone"
    for output, extra in ((tracked, []), (alone, ["--no-tracking"])):
        assert vc_eval([str(bundle), "--video", str(video), "--gt", str(truth), "-o", str(output), "--threads", "1",
                        "--frames", "1:5:2", "--no-hog", "--quiet", *extra]) == 0
    metrics = [json.loads((output / "metrics.json").read_text()) for output in (tracked, alone)]
    assert [m["frames"]["count"] for m in metrics] == [3, 3]
    assert metrics[1]["tracking"] == {"off": "--no-tracking"} and metrics[0]["tracking"]["fps"] == 10
    lines = [[json.loads(line) for line in (output / "detections.jsonl").read_text().splitlines()]
             for output in (tracked, alone)]
    assert [line["frame"] for line in lines[0]] == [line["frame"] for line in lines[1]] == [1, 3, 5]
    # The same boxes: tracking only numbers people and orders their pairs.
    for with_tracks, without in zip(lines[0], lines[1], strict=True):
        assert [p["box"] for p in with_tracks["people"]] == [p["box"] for p in without["people"]]


def test_vc_eval_refuses_frames_past_the_ground_truth(bundle, tmp_path, capsys):
    video, truth = _video_and_truth(tmp_path)
    assert vc_eval([str(bundle), "--video", str(video), "--gt", str(truth), "-o", str(tmp_path / "eval"),
                    "--frames", "1:4", "--no-hog", "--quiet"]) == 2
    assert "past the last annotated frame (3)" in capsys.readouterr().err
    assert not (tmp_path / "eval").exists()
