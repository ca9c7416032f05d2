"""vc-scene edit's library and server (vc.scenes.editor, vc.scenes.editor_server): the scene shown in pixels, an
edit written back in the scene's own frame with the rest of the file untouched, a bad edit refused with the loader's
message and nothing written. The page itself is driven in a real browser by tests/test_scene_editor_browser.py."""

from __future__ import annotations

import json
import re
import shutil
import threading
import urllib.error
import urllib.request
from pathlib import Path

import numpy as np
import pytest
import yaml
from scene_factory import PEOPLE_TRUTH, write_people_scene

from vc.calibration.from_people import camera_of, pose_of
from vc.errors import InputError
from vc.scenes import editor
from vc.scenes.editor_server import serve
from vc.scenes.loader import load_scene

DEMO = Path(__file__).resolve().parents[1] / "examples" / "scenes" / "demo"


@pytest.fixture
def metric_scene(tmp_path) -> Path:
    """The demo scene (a metric layout: frame ground) in a folder of its own."""
    shutil.copytree(DEMO, tmp_path / "demo")
    return tmp_path / "demo" / "scene.yaml"


@pytest.fixture
def pixel_scene(metric_scene) -> Path:
    """The demo's camera and background with a layout drawn in pixels (what vc-scene init writes)."""
    document = yaml.safe_load(metric_scene.read_text())
    document["layout"] = {"frame": "image", "walkable": [[[100, 300], [860, 300], [900, 520], [60, 520]]],
                          "obstacles": [{"type": "cylinder", "name": "post", "base": [480, 400], "radius": 0.1,
                                         "height": 2.0}], "walls": []}
    metric_scene.write_text("# drawn by hand\n" + yaml.safe_dump(document, sort_keys=False))
    return metric_scene


def _edit(state: dict) -> dict:
    return {kind: [dict(element) for element in state[kind]] for kind in ("walkable", "obstacles", "walls", "zones")}


def _folder_files(scene: Path) -> set[str]:
    return {path.name for path in scene.parent.iterdir()}


def test_a_metric_scene_is_shown_in_pixels_through_its_camera(metric_scene):
    state = editor.page_state(metric_scene)
    scene = load_scene(metric_scene)
    assert state["frame"] == "ground" and state["size"] == [960, 540] and state["locked"] == []
    assert (len(state["walkable"]), len(state["obstacles"]), len(state["walls"])) == (2, 7, 1)
    corner = scene.camera.project(np.array([[-5.5, 0.0, 0.0]])).uv[0]
    assert state["walkable"][0]["points"][0] == pytest.approx(corner, abs=0.01)
    assert state["grid"]["step_m"] == 1.0 and len(state["grid"]["lines"]) > 20
    assert [region["name"] for region in state["regions"]] == ["r0", "r1"]


def test_figures_stand_on_the_ground_under_the_mouse_at_the_prior_s_statures(metric_scene):
    camera = load_scene(metric_scene).camera
    shown = editor.figures_at(camera, (480.0, 400.0), (1.5, 1.95))
    ground = camera.ground_from_pixels(np.array([[480.0, 400.0]])).points[0]
    assert shown["ground"] == pytest.approx(ground[:2], abs=1e-3)
    short, tall = shown["figures"]
    assert 0 < short["height_px"] < tall["height_px"] and tall["height_px"] / short["height_px"] == pytest.approx(
        1.95 / 1.5, rel=0.05)
    lowest = max(point[1] for line in short["lines"] for point in line)
    assert lowest == pytest.approx(400.0, abs=3.0)  # the feet are where the mouse is
    assert editor.figures_at(camera, (480.0, -300.0), (1.5,)) == {"ground": None, "figures": []}  # above the horizon


def test_an_unchanged_edit_leaves_the_file_as_it_was(metric_scene, pixel_scene):
    for scene in (pixel_scene,):
        text = scene.read_text()
        assert editor.edited_text(scene, _edit(editor.page_state(scene))) == text


def test_a_moved_metric_point_is_written_in_metres_and_everything_else_as_it_was(metric_scene):
    before = metric_scene.read_text()
    edit = _edit(editor.page_state(metric_scene))
    edit["walkable"][0]["points"][1] = [700.0, 420.0]
    edit["walkable"][0]["edited"] = True
    editor.save(metric_scene, edit)
    after = yaml.safe_load(metric_scene.read_text())
    original = yaml.safe_load(before)
    ground = load_scene(metric_scene).camera.ground_from_pixels(np.array([[700.0, 420.0]])).points[0, :2]
    assert after["layout"]["walkable"][0][1] == pytest.approx(ground, abs=1e-4)
    assert after["layout"]["walkable"][1] == original["layout"]["walkable"][1]
    assert after["layout"]["obstacles"] == original["layout"]["obstacles"]  # not projected there and back
    assert {key: value for key, value in after.items() if key != "layout"} == \
        {key: value for key, value in original.items() if key != "layout"}
    assert metric_scene.read_text().startswith(before.split("layout:")[0])  # the comments above are kept


def test_drawn_elements_keep_their_pixels_in_a_pixel_scene(pixel_scene):
    edit = _edit(editor.page_state(pixel_scene))
    edit["obstacles"].append({"type": "box", "footprint": [[300, 450], [360, 450], [360, 480], [300, 480]],
                              "height": 0.8, "bottom": 0.0, "name": "bench", "source": None, "edited": True})
    edit["walls"].append({"start": [100, 310], "end": [300, 310], "height": 2.0, "thickness": 0.2, "source": None,
                          "edited": True})
    edit["zones"].append({"name": "door", "frame": "image", "points": [[400, 450], [500, 450], [500, 500]],
                          "source": None, "edited": True})
    state = editor.save(pixel_scene, edit)
    layout = yaml.safe_load(pixel_scene.read_text())["layout"]
    assert layout["frame"] == "image" and layout["obstacles"][1]["footprint"][0] == [300, 450]
    assert layout["walls"][0]["start"] == [100, 310]
    assert pixel_scene.read_text().startswith("# drawn by hand\n")
    assert [zone.name for zone in load_scene(pixel_scene).zones] == ["door"]
    assert len(state["obstacles"]) == 2 and state["zones"][0]["points"][0] == [400, 450]


def test_a_deleted_element_is_gone_and_the_others_stay(metric_scene):
    edit = _edit(editor.page_state(metric_scene))
    removed = edit["obstacles"].pop(0)
    edit["removed"] = {"obstacles": [removed["source"]]}
    editor.save(metric_scene, edit)
    names = [obstacle["name"] for obstacle in yaml.safe_load(metric_scene.read_text())["layout"]["obstacles"]]
    assert "lamp post" not in names and len(names) == 6


@pytest.mark.parametrize("change, field", [
    (lambda edit: edit["walkable"].append({"points": [[100, 300], [800, 500], [800, 300], [100, 500]],
                                           "source": None, "edited": True}), "layout.walkable"),  # polygon 2
    (lambda edit: edit["walkable"].append({"points": [[100, -250], [800, 5], [800, 300]], "source": None,
                                           "edited": True}), "layout.walkable.2.0"),  # above the horizon
    (lambda edit: edit["obstacles"].append({"type": "cylinder", "base": [480, 400], "radius": -1, "height": 1,
                                            "source": None, "edited": True}), "layout.obstacles.7.radius"),
])
def test_a_bad_edit_names_the_scene_and_field_and_writes_nothing(metric_scene, change, field):
    before, files = metric_scene.read_bytes(), _folder_files(metric_scene)
    edit = _edit(editor.page_state(metric_scene))
    change(edit)
    with pytest.raises(InputError) as raised:
        editor.save(metric_scene, edit)
    assert raised.value.path == str(metric_scene.resolve()) and raised.value.field == field
    assert metric_scene.read_bytes() == before and _folder_files(metric_scene) == files


def test_check_plans_the_regions_of_an_edit_without_writing(metric_scene):
    before = metric_scene.read_bytes()
    edit = _edit(editor.page_state(metric_scene))
    edit["walkable"] = edit["walkable"][1:]  # the path alone
    edit["removed"] = {"walkable": [0]}
    answer = editor.preview(metric_scene, edit)
    assert answer["walkable_area_m2"] == pytest.approx(2.5 * 2.7, rel=1e-3)
    assert metric_scene.read_bytes() == before


def _request(url: str, body: bytes | None = None) -> tuple[int, dict | bytes]:
    request = urllib.request.Request(url, data=body, headers={"Content-Type": "application/json"} if body else {})
    try:
        with urllib.request.urlopen(request, timeout=30) as response:
            payload = response.read()
            status = response.status
            kind = response.headers.get("Content-Type")
    except urllib.error.HTTPError as error:
        payload, status, kind = error.read(), error.code, error.headers.get("Content-Type")
    return status, json.loads(payload) if kind == "application/json" else payload


def test_the_server_answers_the_page_and_refuses_bad_requests_by_name(pixel_scene):
    server = serve(pixel_scene, port=0)
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    try:
        status, page = _request(server.url)
        assert status == 200 and b"editor.js" in page
        assert not re.search(rb'(src|href)="(https?:)?//', page)  # nothing from outside the machine
        status, image = _request(server.url + "background")
        assert status == 200 and image == (pixel_scene.parent / "background.png").read_bytes()
        status, state = _request(server.url + "api/state")
        assert status == 200 and state["frame"] == "image"
        assert _request(server.url + "api/figures?u=x")[0] == 400
        status, answer = _request(server.url + "api/save", b"not json")
        assert status == 400 and "not JSON" in answer["error"]
        bad = _edit(state)
        bad["walkable"][0] = {"points": [[100, 300], [800, 500], [800, 300], [100, 500]], "source": 0, "edited": True}
        status, answer = _request(server.url + "api/save", json.dumps(bad).encode())
        assert status == 400 and answer["error"].startswith(f"{pixel_scene.resolve()}: layout.walkable")
        assert "polygon 0" in answer["error"]
        assert _request(server.url + "api/nothing")[0] == 404
        status, saved = _request(server.url + "api/save", json.dumps(_edit(state)).encode())
        assert status == 200 and saved["walkable"] == state["walkable"]  # served on after a refused edit
    finally:
        server.shutdown()
        server.server_close()


def test_a_scene_that_does_not_load_is_refused_before_serving(tmp_path):
    (tmp_path / "scene.yaml").write_text("name: broken\n")
    with pytest.raises(InputError):
        serve(tmp_path / "scene.yaml", port=0)


def test_vc_scene_edit_refuses_a_folder_without_a_scene(tmp_path, capsys):
    from vc.cli.scene import main

    assert main(["edit", str(tmp_path)]) == 2
    assert "no scene.yaml here" in capsys.readouterr().err


def test_vc_scene_edit_refuses_a_port_already_taken(pixel_scene, capsys):
    from vc.cli.scene import main

    taken = serve(pixel_scene, port=0)
    try:
        assert main(["edit", str(pixel_scene), "--port", str(taken.server_address[1])]) == 2
        assert "--port: cannot serve on 127.0.0.1" in capsys.readouterr().err
    finally:
        taken.server_close()


@pytest.fixture
def people_scene(tmp_path) -> Path:
    """A scene as vc-scene init VIDEO writes one: the camera solved from people (10 % low), the layout in pixels."""
    return write_people_scene(tmp_path / "people", DEMO / "background.png",
                              [[100, 300], [860, 300], [900, 520], [60, 520]])


def _measured(pixels: list[list[float]]) -> list[dict]:
    """Ground points at ``pixels`` with their positions through the true camera, as the page posts them."""
    truth = camera_of((960, 540), *PEOPLE_TRUTH.values())
    ground = truth.ground_from_pixels(np.array(pixels, float)).points[:, :2].round(3)
    return [{"pixel": pixel, "x": float(x), "y": float(y), "source": None, "edited": True}
            for pixel, (x, y) in zip(pixels, ground, strict=True)]


def test_measured_ground_points_drawn_on_the_page_refine_a_camera_solved_from_people(people_scene):
    state = editor.page_state(people_scene)
    assert state["points"] == [] and state["points_refused"] is None
    assert state["camera"]["height_m"] == pytest.approx(5.85, abs=0.01)
    corners = [[150.0, 300.0], [820.0, 300.0], [200.0, 520.0], [760.0, 520.0]]
    edit = {**_edit(state), "points": _measured(corners)}
    state = editor.save(people_scene, edit)
    calibration = yaml.safe_load(people_scene.read_text())["calibration"]
    assert calibration["format"] == "people" and calibration["path"] == "walkers.json"
    assert [row[:2] for row in calibration["points"]] == corners
    # Four points spread over the view pull the people's camera (10 % low, 2 degrees shallow) to the true one.
    assert state["camera"]["height_m"] == pytest.approx(6.5, rel=0.03)
    assert pose_of(load_scene(people_scene).camera)["tilt_deg"] == pytest.approx(25.0, abs=0.5)
    assert [point["pixel"] for point in state["points"]] == corners
    # An edit that does not speak of points keeps them; one that removes them all drops the key.
    assert "points" in yaml.safe_load(editor.edited_text(people_scene, _edit(state)))["calibration"]
    editor.save(people_scene, {**_edit(state), "points": []})
    assert "points" not in yaml.safe_load(people_scene.read_text())["calibration"]


def test_ground_points_are_refused_by_name_where_they_cannot_refine_the_camera(people_scene, pixel_scene):
    state = editor.page_state(pixel_scene)
    assert "solved from people" in state["points_refused"]
    before = pixel_scene.read_text()
    with pytest.raises(InputError, match="calibration.points: ground points refine a camera solved from people"):
        editor.save(pixel_scene, {**_edit(state), "points": _measured([[200.0, 350.0], [700.0, 330.0]])})
    assert pixel_scene.read_text() == before
    bad = _measured([[200.0, 350.0], [700.0, 330.0]])
    bad[1]["x"] = "four"
    with pytest.raises(InputError, match=r"calibration\.points\.1: a point needs its pixel and its ground x, y"):
        editor.save(people_scene, {**_edit(editor.page_state(people_scene)), "points": bad})
    with pytest.raises(InputError, match="calibration.points: needs at least 2 points, got 1"):
        editor.save(people_scene, {**_edit(editor.page_state(people_scene)), "points": bad[:1]})
