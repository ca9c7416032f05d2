"""Atomic output and image I/O: a failed write leaves the old file and no temporary behind."""

from __future__ import annotations

import numpy as np
import pytest

from vc.errors import InputError
from vc.io import atomic_directory, atomic_path, image_size, read_image, write_image, write_json


def test_image_round_trip_is_exact(tmp_path):
    pixels = np.random.default_rng(1).integers(0, 256, (17, 23, 3), dtype=np.uint8)
    write_image(tmp_path / "a.png", pixels)
    np.testing.assert_array_equal(read_image(tmp_path / "a.png"), pixels)
    assert image_size(tmp_path / "a.png") == (23, 17)


def test_grey_images_read_as_rgb(tmp_path):
    grey = np.arange(12, dtype=np.uint8).reshape(3, 4, 1) * 20
    write_image(tmp_path / "g.png", grey)
    rgb = read_image(tmp_path / "g.png")
    assert rgb.shape == (3, 4, 3) and (rgb[..., 1] == grey[..., 0]).all()


def test_failed_write_keeps_the_old_file_and_leaves_no_temporary(tmp_path):
    target = tmp_path / "result.json"
    write_json(target, {"version": 1})
    with pytest.raises(RuntimeError), atomic_path(target) as temporary:
        temporary.write_text("half")
        raise RuntimeError("crash mid-write")
    assert target.read_text().strip().startswith("{") and '"version": 1' in target.read_text()
    assert [p.name for p in tmp_path.iterdir()] == ["result.json"]


def test_unreadable_images_are_input_errors(tmp_path):
    (tmp_path / "bad.png").write_bytes(b"\x89PNG but not really")
    with pytest.raises(InputError, match="bad.png"):
        read_image(tmp_path / "bad.png")
    with pytest.raises(InputError, match="image file not found"):
        image_size(tmp_path / "absent.png")


def test_a_failed_folder_write_keeps_the_old_folder_and_leaves_no_staging(tmp_path):
    output = tmp_path / "bundle"
    with atomic_directory(output) as staging:
        (staging / "a.txt").write_text("old")
    with pytest.raises(RuntimeError), atomic_directory(output) as staging:
        (staging / "a.txt").write_text("new")
        raise RuntimeError("crash half-way")
    assert (output / "a.txt").read_text() == "old"
    assert [path.name for path in tmp_path.iterdir()] == ["bundle"]
    with atomic_directory(output) as staging:
        (staging / "b.txt").write_text("new")
    assert sorted(path.name for path in output.iterdir()) == ["b.txt"]


def test_a_folder_under_a_file_is_an_input_error(tmp_path):
    (tmp_path / "file").write_text("")
    with pytest.raises(InputError, match="cannot create output folder"), \
            atomic_directory(tmp_path / "file" / "bundle"):
        pass


def test_temporaries_a_killed_writer_left_are_cleared_by_the_next_write(tmp_path):
    """A SIGKILL between creating a temporary and renaming it leaves the temporary behind; the next write of the
    same output removes it (one output has one writer at a time), and leaves other outputs' temporaries alone."""
    (tmp_path / ".out.json.x1y2.tmp.json").write_text("half")
    (tmp_path / ".bundle.k3.tmp").mkdir()
    (tmp_path / ".other.json.z9.tmp.json").write_text("someone else's")
    write_json(tmp_path / "out.json", {"a": 1})
    with atomic_directory(tmp_path / "bundle") as staging:
        (staging / "m").write_text("x")
    assert sorted(path.name for path in tmp_path.iterdir()) == [".other.json.z9.tmp.json", "bundle", "out.json"]


def test_a_write_that_finds_no_room_is_an_output_error_naming_the_file(tmp_path, monkeypatch):
    import errno
    import os

    from vc.errors import OutputError, StageError

    write_json(tmp_path / "out.json", {"kept": True})

    def full_disk(source, destination):
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    monkeypatch.setattr(os, "replace", full_disk)
    with pytest.raises(OutputError, match=f"cannot write {tmp_path / 'out.json'}: No space left on device") as error:
        write_json(tmp_path / "out.json", {"kept": False})
    assert isinstance(error.value, StageError)  # exit status 1: good input, no room
    assert (tmp_path / "out.json").read_text() == '{\n  "kept": true\n}\n'
    assert [path.name for path in tmp_path.iterdir()] == ["out.json"]
