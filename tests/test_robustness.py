"""benchmarks/robustness.py: each camera-life condition does what it says, COCO-C's corruptions are drawn from their
seeds, mPC and rPC on a known table, and a run on the test bundle that reports every condition."""

from __future__ import annotations

import json

import cv2
import numpy as np
import onnx
import pytest
from dataset_factory import INPUT_SIZE, region_camera, sample
from onnx import TensorProto, helper

from benchmarks import robustness
from benchmarks.robustness import (
    AS_REPORTED,
    AT_OPERATING_POINT,
    CAMERA_LIFE,
    COCO_C,
    SRGB,
    Condition,
    Measurement,
    camera_life_conditions,
    clean_condition,
    exposure,
    gaussian_blur,
    image_motion,
    ir_monochrome,
    moved_boxes,
    nudge,
    performance_under_corruption,
    roll,
    summarise,
    white_balance,
)
from vc.evaluation.baselines import YoloPoseOnnx
from vc.evaluation.metrics import ImageResult
from vc.evaluation.real_video import OURS

RNG = np.random.default_rng(62)
#: A frame whose light can go up a stop without clipping (level 120 is linear 0.19).
FRAME = RNG.integers(30, 120, (48, 64, 3), dtype=np.uint8)


def _linear_mean(frame: np.ndarray) -> np.ndarray:
    return SRGB.decode(frame).reshape(-1, 3).mean(axis=0)


@pytest.mark.parametrize("stops", [-2, -3, 1])
def test_exposure_scales_the_linear_light_by_two_to_the_stops(stops):
    ratio = _linear_mean(exposure(FRAME, stops)).sum() / _linear_mean(FRAME).sum()
    assert ratio == pytest.approx(2.0 ** stops, rel=0.01)  # -2 stops: a quarter of the light
    assert exposure(np.full((4, 4, 3), 200, np.uint8), 1).max() == 255  # more light than white clips


def test_white_balance_scales_red_and_blue_in_linear_light():
    warm = _linear_mean(white_balance(FRAME, red=1.25, blue=0.8)) / _linear_mean(FRAME)
    assert warm == pytest.approx([1.25, 1.0, 0.8], rel=0.01)
    cool = _linear_mean(white_balance(FRAME, red=0.8, blue=1.25)) / _linear_mean(FRAME)
    assert cool == pytest.approx([0.8, 1.0, 1.25], rel=0.01)
    conditions = camera_life_conditions()
    red_over_blue = [(lambda m: m[0] / m[2])(_linear_mean(conditions[key].transform(FRAME, 0)))
                     for key in ("cool", "warm")]
    assert red_over_blue[0] < _linear_mean(FRAME)[0] / _linear_mean(FRAME)[2] < red_over_blue[1]


def test_ir_monochrome_keeps_the_luminance_in_every_channel():
    grey = ir_monochrome(FRAME)
    assert np.array_equal(grey[..., 0], grey[..., 1]) and np.array_equal(grey[..., 1], grey[..., 2])
    luminance = SRGB.decode(FRAME) @ np.array([0.2126, 0.7152, 0.0722], np.float32)
    assert SRGB.decode(grey)[..., 0].mean() == pytest.approx(luminance.mean(), rel=0.01)
    flat = np.full((4, 4, 3), 90, np.uint8)  # a grey stays the grey it was
    assert np.abs(ir_monochrome(flat).astype(int) - 90).max() <= 1


def test_gaussian_blur_spreads_a_line_by_its_sigma():
    line = np.zeros((9, 41, 3), np.uint8)
    line[:, 20] = 255
    profile = gaussian_blur(line, 2.0)[4, :, 0].astype(float)
    offsets = np.arange(41) - 20
    assert np.sqrt(np.sum(profile * offsets ** 2) / profile.sum()) == pytest.approx(2.0, rel=0.1)


def test_a_nudge_moves_the_content_and_the_truth_by_as_many_pixels():
    moved = nudge(FRAME, 12)
    assert np.array_equal(moved[:, 12:], FRAME[:, :-12])
    assert np.array_equal(moved[:, :12], np.repeat(FRAME[:, :1], 12, axis=1))  # the edge replicated
    down = nudge(FRAME, -5, 3)
    assert np.array_equal(down[3:, :-5], FRAME[:-3, 5:])
    boxes, ignore = moved_boxes(np.array([[10.0, 5, 30, 40], [40, 5, 60, 40]]), image_motion((64, 48), (12, 3)),
                                (64, 48))
    assert boxes.tolist() == [[22, 8, 42, 43], [52, 8, 64, 43]]  # clipped at the frame's right edge
    assert ignore.tolist() == [False, False]  # 12 of 20 px still in the frame
    _, ignore = moved_boxes(np.array([[50.0, 5, 60, 40]]), image_motion((64, 48), (12, 0)), (64, 48))
    assert ignore.tolist() == [True]  # 2 of 10 px left: not asked for
    condition = camera_life_conditions(7)["nudge"]
    assert condition.shift == (7, 0) and np.array_equal(condition.transform(FRAME, 0), nudge(FRAME, 7))


def test_a_roll_turns_the_content_about_the_centre_and_the_truth_follows():
    width, height = 201, 101
    frame = np.zeros((height, width, 3), np.uint8)
    frame[45:56, 175:186] = 255  # a bright square 80 px right of the centre (100, 50)
    weights = roll(frame, 2.0)[..., 0].astype(float)
    rows, columns = np.indices(weights.shape)
    x, y = (columns * weights).sum() / weights.sum(), (rows * weights).sum() / weights.sum()
    # counter-clockwise on the screen: a point right of the centre goes up by 80 sin 2 degrees
    assert x == pytest.approx(100 + 80 * np.cos(np.radians(2)), abs=0.1)
    assert y == pytest.approx(50 - 80 * np.sin(np.radians(2)), abs=0.1)
    assert np.array_equal(roll(frame, 0.0), frame)
    box = np.array([[175.0, 45, 186, 56]])
    moved, ignore = moved_boxes(box, image_motion((width, height), roll_deg=2.0), (width, height))
    # the box follows its content's centre and keeps its size
    assert (moved[0, 0] + moved[0, 2]) / 2 == pytest.approx(x + 0.5, abs=0.1)  # boxes' coordinates: pixel edges
    assert (moved[0, 1] + moved[0, 3]) / 2 == pytest.approx(y + 0.5, abs=0.1)
    assert moved[0, 2] - moved[0, 0] == pytest.approx(11) and not ignore[0]
    condition = camera_life_conditions(roll_deg=0.75)["roll"]
    assert condition.roll_deg == 0.75 and condition.shift == (0, 0)
    assert np.array_equal(condition.transform(FRAME, 0), roll(FRAME, 0.75))


def test_frames_that_replace_the_scene():
    conditions = camera_life_conditions()
    assert not conditions["black"].transform(FRAME, 0).any()
    assert (conditions["grey"].transform(FRAME, 0) == 128).all()
    noise = conditions["noise"].transform(FRAME, 3)
    assert noise.shape == FRAME.shape and noise.dtype == np.uint8 and noise.std() > 60
    assert np.array_equal(noise, conditions["noise"].transform(FRAME, 3))
    assert not np.array_equal(noise, conditions["noise"].transform(FRAME, 4))
    assert {key for key, condition in conditions.items() if condition.background_only} == {"black", "grey", "noise"}
    assert all(condition.family == CAMERA_LIFE for condition in conditions.values())


@pytest.mark.parametrize("corruption", ["gaussian_noise", "impulse_noise", "glass_blur", "frost", "fog", "snow",
                                        "elastic_transform"])
def test_corruptions_are_drawn_from_their_seed(corruption):
    pytest.importorskip("imagecorruptions")
    frame = RNG.integers(0, 256, (48, 64, 3), dtype=np.uint8)
    condition = robustness.coco_c_conditions([corruption], [3])[0]
    assert condition.family == COCO_C and condition.key == f"{corruption}/3"
    state = np.random.get_state()  # noqa: NPY002 - the global generator is put back as it was
    first = condition.transform(frame, robustness.condition_seed(condition.key, "1"))
    assert np.random.get_state()[1].tolist() == state[1].tolist()  # noqa: NPY002
    assert first.shape == frame.shape and first.dtype == np.uint8 and not np.array_equal(first, frame)
    assert np.array_equal(first, condition.transform(frame, robustness.condition_seed(condition.key, "1")))
    assert not np.array_equal(first, condition.transform(frame, robustness.condition_seed(condition.key, "2")))


def test_mpc_and_rpc_of_a_known_table():
    assert performance_under_corruption([0.8, 0.6, 0.4, 0.2], 0.8) == pytest.approx((0.5, 0.625))
    assert performance_under_corruption([0.3], 0.0) == (0.3, None)
    truth = np.array([[0.0, 0, 10, 20], [20, 0, 30, 20]])

    def found(count: int) -> list[ImageResult]:  # an image in which the first ``count`` people are found
        return [ImageResult(truth, truth[:count], np.linspace(0.9, 0.8, count))]

    def condition(key: str, family: str, background_only: bool = False) -> Condition:
        return Condition(key, key, family, lambda frame, seed: frame, background_only=background_only)

    def measurement(condition: Condition, ours: int, theirs: int, background: list[float]) -> Measurement:
        images = {} if condition.background_only else {OURS: found(ours), "yolo": found(theirs)}
        return Measurement(condition, images, {OURS: np.array(background), "yolo": np.array([0.3, 0.2])})

    report = summarise([measurement(clean_condition(), 2, 2, []),
                        measurement(condition("a", CAMERA_LIFE), 1, 2, [0.95, 0.1]),
                        measurement(condition("b", CAMERA_LIFE), 0, 1, [0.85]),
                        measurement(condition("black", CAMERA_LIFE, True), 0, 0, [0.99, 0.98, 0.97]),
                        measurement(condition("c/1", COCO_C), 1, 1, [])], external="yolo")
    # clean AP50 1.0 for both: their operating point is the weakest clean detection, 0.8
    assert report["operating_points"][AT_OPERATING_POINT] == pytest.approx(0.8)
    rows = {row["key"]: row for row in report["conditions"]}
    assert rows["a"]["ap50"] == {OURS: 0.5, "yolo": 1.0} and "ap50" not in rows["black"]
    life = report["families"][CAMERA_LIFE]
    assert life["conditions"] == 3 and life["scored_conditions"] == 2
    assert life["mPC"] == {OURS: 0.25, "yolo": 0.75} and life["rPC"] == {OURS: 0.25, "yolo": 0.75}
    assert report["families"][COCO_C]["mPC"] == {OURS: 0.5, "yolo": 0.5}
    assert rows["a"]["false_people"] == {AT_OPERATING_POINT: 1, AS_REPORTED: 2, "yolo at score >= 0.25": 1}
    # per frame: (1 + 1 + 3) / 3 at the operating point, (2 + 1 + 3) / 3 as reported
    assert life["false_people_per_frame"] == {AT_OPERATING_POINT: pytest.approx(1.667),
                                              AS_REPORTED: 2.0, "yolo at score >= 0.25": 1.0}


def _constant_yolo(path, box: list[float], size: int = 64, score: float = 0.9) -> None:
    """A YOLO-pose style model (1, 56, 1) that reports one person at ``box`` of a 128x64 frame (letterboxed into
    ``size``: scale 0.5, 16 px padding at the top) with ``score``, whatever the frame."""
    x0, y0, x1, y1 = np.asarray(box) * 0.5 + np.array([0, 16, 0, 16])
    row = np.zeros(56, np.float32)
    row[:5] = (x0 + x1) / 2, (y0 + y1) / 2, x1 - x0, y1 - y0, score
    nodes = [helper.make_node("ReduceMean", ["images"], ["mean"], axes=[1, 2, 3], keepdims=0),
             helper.make_node("Mul", ["mean", "zero"], ["nothing"]),
             helper.make_node("Add", ["nothing", "row"], ["output0"])]
    graph = helper.make_graph(
        nodes, "constant-yolo", [helper.make_tensor_value_info("images", TensorProto.FLOAT, (1, 3, size, size))],
        [helper.make_tensor_value_info("output0", TensorProto.FLOAT, (1, 56, 1))],
        initializer=[helper.make_tensor("row", TensorProto.FLOAT, (1, 56, 1), row),
                     helper.make_tensor("zero", TensorProto.FLOAT, (), [0.0])])
    onnx.save(helper.make_model(graph, opset_imports=[helper.make_opsetid("", 17)], ir_version=8), path)


def test_a_yolo_model_that_finds_nobody_returns_no_people(tmp_path):
    _constant_yolo(tmp_path / "yolo.onnx", [40.0, 10.0, 60.0, 50.0], score=1e-4)  # below the model's score floor
    boxes, scores, keypoints = YoloPoseOnnx(tmp_path / "yolo.onnx")(np.zeros((64, 128, 3), np.uint8))
    assert boxes.shape == (0, 4) and scores.shape == (0,) and keypoints.shape == (0, 17, 3)


def test_a_run_on_the_test_bundle_reports_every_condition(bundle, tmp_path, capsys):
    box = [40.0, 10.0, 60.0, 50.0]
    writer = cv2.VideoWriter(str(tmp_path / "clip.avi"), cv2.VideoWriter_fourcc(*"MJPG"), 10, INPUT_SIZE)
    for index in range(4):
        writer.write(np.ascontiguousarray(sample(region_camera(), index, seed=9).image[:, :, ::-1]))
    writer.release()
    (tmp_path / "gt.txt").write_text("".join(f"{n},1,40,10,20,40,1,-1,-1,-1\n" for n in (1, 2, 3)))
    cv2.imwrite(str(tmp_path / "background.png"), np.full((INPUT_SIZE[1], INPUT_SIZE[0], 3), 100, np.uint8))
    _constant_yolo(tmp_path / "yolo.onnx", box)
    try:
        import imagecorruptions  # noqa: F401
        corruptions = ["gaussian_noise", "motion_blur"]
    except ImportError:
        corruptions = []
    arguments = [str(bundle), "--video", str(tmp_path / "clip.avi"), "--gt", str(tmp_path / "gt.txt"),
                 "--frames", "1:3", "--background", str(tmp_path / "background.png"),
                 "--external", str(tmp_path / "yolo.onnx"), "--corruptions", *corruptions, "--severities", "1", "3",
                 "--threads", "1", "--quiet"]
    assert robustness.main([*arguments, "--out", str(tmp_path / "first")]) == 0
    report = json.loads((tmp_path / "first" / "robustness.json").read_text())
    keys = ["clean", *camera_life_conditions(), *(f"{name}/{s}" for name in corruptions for s in (1, 3))]
    assert [row["key"] for row in report["conditions"]] == keys
    assert report["frames"]["count"] == 3 and report["people"] == 3 and report["severities"] == [1, 3]
    assert report["detectors"] == [OURS, "yolo.onnx @64"] and report["machine"]
    assert report["command"].startswith("python -m benchmarks.robustness bundle --video clip.avi --gt gt.txt "
                                        "--frames 1:3:1 --background background.png --external yolo.onnx ")
    assert report["bundle"]["path"] == "bundle" and report["bundle"]["models_sha256"]
    rows = {row["key"]: row for row in report["conditions"]}
    assert "ap50" not in rows["black"] and set(rows["black"]["false_people"]) == set(report["operating_points"])
    # the constant model finds the person, and reports one on the background, under every condition but the nudge,
    # where the truth moved away from its box
    yolo = "yolo.onnx @64"
    assert all(row["ap50"][yolo] == 1.0 for key, row in rows.items() if "ap50" in row and key != "nudge")
    assert rows["nudge"]["ap50"][yolo] == 0.0
    assert all(row["false_people"][f"{yolo} at score >= 0.25"] == 1 for row in rows.values())
    assert report["families"][CAMERA_LIFE]["rPC"][yolo] == pytest.approx(8 / 9, abs=1e-4)
    # the choosing half is frames 1-2 of 1-3, the confirming frame 3; the nudge loses the constant model both
    assert report["halves"] == {"choosing": {"first": 1, "last": 2, "count": 2},
                                "confirming": {"first": 3, "last": 3, "count": 1}}
    assert rows["nudge"]["ap50_by_half"]["confirming"][yolo] == 0.0
    assert all(report["families"][CAMERA_LIFE]["by_half"][half]["rPC"][yolo] == pytest.approx(8 / 9, abs=1e-4)
               for half in ("choosing", "confirming"))
    markdown = (tmp_path / "first" / "robustness.md").read_text()
    assert all(row["label"] in markdown for row in report["conditions"]) and report["machine"] in markdown
    assert "## Choosing and confirming halves" in markdown and "| confirming | 3–3 (1) |" in markdown
    assert (tmp_path / "first" / "robustness.png").stat().st_size > 0
    assert "robustness: 3 frames" in capsys.readouterr().out
    # a rerun changes the frames to the same bytes: the same numbers (every annotated frame, 1-3, by default)
    rerun = [word for word in arguments if word not in ("--frames", "1:3")]
    assert robustness.main([*rerun, "--conditions", "noise", "blur", "--out", str(tmp_path / "again")]) == 0
    second = json.loads((tmp_path / "again" / "robustness.json").read_text())
    assert " --frames 1:3:1 " in second["command"] and " --conditions noise blur " in second["command"]
    again = {row["key"]: row for row in second["conditions"]}
    assert all(again[key][field] == rows[key][field] for key in again for field in ("ap50", "false_people")
               if field in rows[key])


def test_unknown_conditions_are_refused(tmp_path, capsys):
    with pytest.raises(SystemExit):
        robustness.main([str(tmp_path / "bundle"), "--video", str(tmp_path / "none.avi"), "--gt",
                         str(tmp_path / "gt.txt"), "--conditions", "fog of war", "--corruptions",
                         "--out", str(tmp_path / "out")])
    assert "unknown fog of war" in capsys.readouterr().err
    assert not (tmp_path / "out").exists()
