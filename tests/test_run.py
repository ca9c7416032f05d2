"""vc-run and its frame reader: images, folders and videos in, JSON Lines and overlays out; bad input refused
with exit status 2 and nothing written."""

from __future__ import annotations

import argparse
import json
import re

import cv2
import numpy as np
import pytest
from dataset_factory import INPUT_SIZE, region_camera, sample

from vc.cli.run import main as vc_run
from vc.deploy.frames import FrameRange, FrameSource
from vc.errors import InputError
from vc.io import write_image


def _frames(count: int) -> list[np.ndarray]:
    """Test-dataset images, each with a band of its own grey level at the top so that no two are alike."""
    frames = [sample(region_camera(), index, seed=3).image for index in range(count)]
    for index, frame in enumerate(frames):
        frame[:16] = 30 * index
    return frames


def _video(path, frames: list[np.ndarray]) -> None:
    writer = cv2.VideoWriter(str(path), cv2.VideoWriter_fourcc(*"MJPG"), 10, INPUT_SIZE)
    for frame in frames:
        writer.write(np.ascontiguousarray(frame[:, :, ::-1]))
    writer.release()


@pytest.mark.parametrize(("text", "expected"), [("1:400:5", FrameRange(1, 400, 5)), ("::10", FrameRange(1, None, 10)),
                                                ("100:", FrameRange(100, None, 1)), ("7", FrameRange(7, None, 1))])
def test_frame_ranges_parse(text, expected):
    assert FrameRange.parse(text) == expected


@pytest.mark.parametrize("text", ["0:10", "5:4", "1:2:0", "a:b", "1:2:3:4"])
def test_bad_frame_ranges_are_refused(text):
    with pytest.raises(argparse.ArgumentTypeError):
        FrameRange.parse(text)


def test_a_selection_counts_and_yields_the_same_frames(tmp_path):
    frames = _frames(7)
    _video(tmp_path / "clip.avi", frames)
    selection = FrameRange(2, 6, 2)
    source = FrameSource(tmp_path / "clip.avi", selection)
    read = list(source)
    assert len(source) == 3 and [frame.number for frame in read] == [2, 4, 6]
    # MJPG is lossy: the frames are the right ones if each is closest to its original.
    for frame in read:
        errors = [np.abs(frame.image.astype(int) - original).mean() for original in frames]
        assert int(np.argmin(errors)) == frame.number - 1


@pytest.mark.parametrize(("content", "message"), [(b"", "cannot open as a video|no readable frame"),
                                                  (b"RIFF\x00\x00garbage" * 50, "cannot open as a video|no readable")])
def test_unreadable_videos_are_input_errors(tmp_path, content, message):
    (tmp_path / "bad.avi").write_bytes(content)
    with pytest.raises(InputError, match=message):
        FrameSource(tmp_path / "bad.avi")


def test_an_empty_folder_and_an_empty_selection_are_input_errors(tmp_path):
    with pytest.raises(InputError, match="no image files"):
        FrameSource(tmp_path)
    write_image(tmp_path / "a.png", _frames(1)[0])
    with pytest.raises(InputError, match="holds none"):
        FrameSource(tmp_path, FrameRange(5))


def test_vc_run_writes_one_line_per_frame_and_overlays(bundle, tmp_path):
    folder = tmp_path / "frames"
    for index, frame in enumerate(_frames(3)):
        write_image(folder / f"f{index:02d}.png", frame)
    output = tmp_path / "out"
    assert vc_run([str(bundle), str(folder), "-o", str(output), "--overlay", "--threads", "1", "--quiet"]) == 0
    lines = [json.loads(line) for line in (output / "detections.jsonl").read_text().splitlines()]
    assert [line["frame"] for line in lines] == [1, 2, 3] and lines[0]["name"] == "f00.png"
    summary = json.loads((output / "summary.json").read_text())
    assert summary["frames"] == 3 and summary["people"] == sum(len(line["people"]) for line in lines)
    assert sorted(path.name for path in (output / "overlays").iterdir()) == ["f00.png", "f01.png", "f02.png"]
    # A folder of frames has no time: not tracked unless its rate is given.
    assert summary["tracking"] is None and not any("track" in p for line in lines for p in line["people"])
    tracked = tmp_path / "tracked"
    assert vc_run([str(bundle), str(folder), "-o", str(tracked), "--fps", "5", "--threads", "1", "--quiet"]) == 0
    tracking = json.loads((tracked / "summary.json").read_text())["tracking"]
    assert tracking["fps"] == 5 and isinstance(tracking["tracks"], int) and isinstance(tracking["people_carried"], int)


def test_vc_run_on_a_video_writes_an_overlay_video(bundle, tmp_path):
    _video(tmp_path / "clip.avi", _frames(4))
    output = tmp_path / "out"
    assert vc_run([str(bundle), str(tmp_path / "clip.avi"), "-o", str(output), "--overlay", "--frames", "::2",
                   "--quiet"]) == 0
    assert [json.loads(line)["frame"] for line in (output / "detections.jsonl").read_text().splitlines()] == [1, 3]
    overlay = cv2.VideoCapture(str(output / "overlay.mp4"))
    assert overlay.get(cv2.CAP_PROP_FRAME_COUNT) == 2 and overlay.get(cv2.CAP_PROP_FRAME_WIDTH) == INPUT_SIZE[0]


@pytest.mark.parametrize("case", ["wrong size", "bad video", "bad bundle"])
def test_vc_run_refuses_bad_input_and_writes_nothing(bundle, tmp_path, capsys, case):
    bundle_path, input_path = bundle, tmp_path / "frames"
    input_path.mkdir()
    write_image(input_path / "a.png", _frames(1)[0])
    if case == "wrong size":
        write_image(input_path / "b.png", np.zeros((INPUT_SIZE[1] + 2, INPUT_SIZE[0], 3), np.uint8))
        expected = "frame 2 \\(b.png\\): is 128x66"
    elif case == "bad video":
        input_path = tmp_path / "empty.avi"
        input_path.write_bytes(b"")
        expected = "empty.avi"
    else:
        bundle_path = tmp_path / "bundle.zip"
        bundle_path.write_bytes(b"PK\x03\x04 not really a zip")
        expected = "bundle.zip"
    assert vc_run([str(bundle_path), str(input_path), "-o", str(tmp_path / "out"), "--overlay", "--quiet"]) == 2
    assert re.search(expected, capsys.readouterr().err)
    assert not (tmp_path / "out").exists() and not list(tmp_path.glob(".out.*"))


def _person_at(region: str, score: float, box: list[float]):
    from vc.deploy.runtime import Person

    return Person(region, score, np.array(box, float), np.zeros((17, 3)), np.zeros((0, 0), bool), (0, 0))


def test_one_person_kept_by_two_regions_at_their_seam_is_reported_once() -> None:
    """PETS09 frame 1: one walker kept by r1 (feet at y 319, its side of the seam) and by r2 (y 323, its side)."""
    from vc.deploy.runtime import without_seam_duplicates

    r1, r2 = _person_at("r1", 1.02, [641, 237, 684, 319]), _person_at("r2", 0.77, [640, 242, 684, 323])
    assert without_seam_duplicates([r1, r2]) == [r1]
    # One region's people overlapping as much are two people (one behind another): the decoder separated them.
    behind = _person_at("r1", 0.77, [640, 242, 684, 323])
    assert without_seam_duplicates([r1, behind]) == [r1, behind]
    # People of two regions side by side stay two.
    beside = _person_at("r2", 0.77, [670, 240, 712, 322])
    assert without_seam_duplicates([r1, beside]) == [r1, beside]


def test_a_region_keeps_people_just_across_a_seam_but_not_beyond_the_outer_edge() -> None:
    """Feet a few pixels into the neighbour's area are the box bottom's error, not another region's person; ground
    no region owns stays unowned."""
    from vc.deploy.areas import ImageArea
    from vc.deploy.runtime import SEAM_FOOT_TOLERANCE, just_across_seam

    def band(y0: float, y1: float) -> ImageArea:
        return ImageArea({"type": "Polygon", "coordinates": [[[0, y0], [100, y0], [100, y1], [0, y1], [0, y0]]]})

    own, neighbour = band(0, 100), band(100, 200)
    height = 80.0
    reach = SEAM_FOOT_TOLERANCE * height
    feet = np.array([[50, 50], [50, 100 + 0.9 * reach], [50, 100 + 1.5 * reach], [50, -0.5 * reach],
                     [150, 100 + 0.5 * reach]])
    heights = np.full(len(feet), height)
    # in its own area (kept as its own), just across, too far across, beyond the outer edge, beside the neighbour
    assert just_across_seam(feet, heights, own, (neighbour,)).tolist() == [False, True, False, False, False]
    # Without neighbours (a one-region bundle) there is no seam to keep anyone across.
    assert not just_across_seam(feet, heights, own, ()).any()
    # The tolerance is a parameter (an experiment measures others): at 0 a region keeps only its own area.
    assert not just_across_seam(feet, heights, own, (neighbour,), tolerance=0.0).any()
    assert just_across_seam(feet, heights, own, (neighbour,), tolerance=2 * SEAM_FOOT_TOLERANCE).tolist() == \
        [False, True, True, False, False]


def test_a_person_the_frame_cuts_is_boxed_as_the_camera_shows_them() -> None:
    """TUD-Stadtmitte's annotators box a person walking in at the right edge up to the edge; a decoded box laid at
    the person's expected width reaches past it and is clipped to the frame's outer edges, not moved."""
    from vc.deploy.runtime import within_frame

    cut = _person_at("r0", 0.8, [610.0, 100.0, 671.0, 330.0])
    assert within_frame(cut, (640, 480)) is cut and cut.box.tolist() == [610.0, 100.0, 639.5, 330.0]
    corner = within_frame(_person_at("r0", 0.8, [-12.0, -3.0, 20.0, 490.0]), (640, 480))
    assert corner.box.tolist() == [-0.5, -0.5, 20.0, 479.5]
    inside = [100.0, 100.0, 140.0, 200.0]
    assert within_frame(_person_at("r0", 0.8, inside), (640, 480)).box.tolist() == inside


def test_at_a_seam_the_owning_regions_person_wins_over_one_kept_across_it() -> None:
    """The region that kept a person across its seam gives way to the region whose area the feet are in, even
    when its score is higher; the people come back strongest first."""
    from vc.deploy.runtime import without_seam_duplicates

    across = _person_at("r1", 1.02, [641, 237, 684, 319])
    across.across_seam = True
    owner = _person_at("r2", 0.77, [640, 242, 684, 323])
    other = _person_at("r1", 0.9, [100, 200, 140, 280])
    assert without_seam_duplicates([across, other, owner]) == [other, owner]
    # Kept across a seam but found by nobody else: reported.
    assert without_seam_duplicates([across, other]) == [across, other]
    # Already a partial overlap with the owner's person is that person (IoU 0.47 here).
    beside = _person_at("r2", 0.5, [655, 240, 699, 322])
    assert without_seam_duplicates([across, beside]) == [beside]
    # A weak owner's person (kept for a tracker only) takes no one's place.
    weak_owner = _person_at("r2", 0.2, [640, 242, 684, 323])
    weak_owner.weak = True
    assert without_seam_duplicates([across, weak_owner]) == [across]
