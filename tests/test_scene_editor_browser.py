"""vc-scene edit in a real browser: the system's Chromium, driven by Playwright, draws a walkable polygon, moves a
vertex, adds an obstacle and saves; the YAML read back holds what was drawn. On a camera solved from people it adds
measured ground points, which refine the camera. A bad edit shows the loader's message on
the page and writes nothing. Any error the page raises fails the test."""

from __future__ import annotations

import os
import shutil
import threading
from pathlib import Path

import numpy as np
import pytest
import yaml
from scene_factory import PEOPLE_TRUTH, write_people_scene

from vc.calibration.from_people import camera_of, pose_of
from vc.scenes.editor_server import serve
from vc.scenes.loader import load_scene

playwright = pytest.importorskip("playwright.sync_api", reason="Playwright is a dev dependency: make install")
CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")
pytestmark = pytest.mark.skipif(CHROMIUM is None, reason="no system Chromium (Debian's chromium package; make install "
                                                         "installs it)")
DEMO = Path(__file__).resolve().parents[1] / "examples" / "scenes" / "demo"
WALKABLE = [[100, 300], [860, 300], [900, 520], [60, 520]]
REFUSED = "console: Failed to load resource: the server responded with a status of 400 (Bad Request)"


@pytest.fixture
def scene(tmp_path) -> Path:
    """The demo's camera and background with a layout drawn in pixels, as vc-scene init writes one."""
    shutil.copytree(DEMO, tmp_path / "demo")
    path = tmp_path / "demo" / "scene.yaml"
    document = yaml.safe_load(path.read_text())
    document["layout"] = {"frame": "image", "walkable": [WALKABLE], "obstacles": [], "walls": []}
    path.write_text(yaml.safe_dump(document, sort_keys=False))
    return path


@pytest.fixture
def page(scene):
    yield from _page(scene)


@pytest.fixture
def people_scene(tmp_path) -> Path:
    """A scene whose camera was solved from the people walking through its video (10 % low), as init writes it."""
    return write_people_scene(tmp_path / "people", DEMO / "background.png", WALKABLE)


@pytest.fixture
def people_page(people_scene):
    yield from _page(people_scene)


def _page(scene: Path):
    """The editor served for ``scene`` and open in Chromium; fails on any error the page raises."""
    server = serve(scene, port=0)
    threading.Thread(target=server.serve_forever, daemon=True).start()
    errors: list[str] = []
    with playwright.sync_playwright() as driver:
        browser = driver.chromium.launch(executable_path=CHROMIUM,
                                         args=["--no-sandbox"] if os.geteuid() == 0 else [])
        tab = browser.new_page(viewport={"width": 1400, "height": 900})
        tab.on("pageerror", lambda error: errors.append(f"page error: {error}"))
        tab.on("console", lambda message: message.type == "error" and errors.append(f"console: {message.text}"))
        tab.goto(server.url)
        tab.wait_for_selector("body[data-ready=true]")
        tab.errors = errors
        yield tab
        browser.close()
    server.shutdown()
    server.server_close()
    # the browser logs the refused save's answer (400) as a failed load; nothing else may fail
    assert [error for error in errors if error != REFUSED] == []


def _screen(page, u: float, v: float) -> tuple[float, float]:
    """The page coordinates of background pixel (u, v)."""
    return tuple(page.evaluate("([u, v]) => { const m = document.getElementById('view').getScreenCTM();"
                               " return [m.a * u + m.c * v + m.e, m.b * u + m.d * v + m.f]; }", [u, v]))


def _click(page, u: float, v: float) -> None:
    page.mouse.click(*_screen(page, u, v))


def _saved(page) -> None:
    page.click("#save")
    page.wait_for_selector("#message.ok, #message.error")


def test_draw_move_add_and_save_in_a_real_browser(page, scene):
    page.click("[data-tool=walkable]")
    drawn = [[200, 350], [400, 350], [400, 450], [200, 450]]
    for u, v in drawn:
        _click(page, u, v)
    page.click("#finish")

    page.click("[data-tool=select]")
    _click(page, 700, 480)  # inside the first walkable polygon, outside the new one
    handle = page.locator("[data-handle-kind=walkable][data-handle-index='0'][data-handle-point='0']")
    assert handle.count() == 1
    page.mouse.move(*_screen(page, 100, 300))
    page.mouse.down()
    page.mouse.move(*_screen(page, 150, 320), steps=5)
    page.mouse.up()

    page.click("[data-tool=cylinder]")
    _click(page, 600, 400)
    page.fill("#prop-height", "1.4")
    page.press("#prop-height", "Enter")
    page.fill("#prop-name", "bin")
    page.press("#prop-name", "Enter")

    _saved(page)
    assert "saved" in page.inner_text("#message") and page.errors == []
    layout = yaml.safe_load(scene.read_text())["layout"]
    assert layout["frame"] == "image" and len(layout["walkable"]) == 2
    assert layout["walkable"][0][0] == pytest.approx([150, 320], abs=1.0)
    assert layout["walkable"][0][1:] == WALKABLE[1:]
    assert np.asarray(layout["walkable"][1]) == pytest.approx(np.asarray(drawn), abs=1.0)
    (bin_,) = layout["obstacles"]
    assert bin_["type"] == "cylinder" and bin_["name"] == "bin" and bin_["height"] == 1.4 and bin_["radius"] == 0.3
    assert bin_["base"] == pytest.approx([600, 400], abs=1.0)


def test_a_bad_edit_shows_the_loader_s_message_and_writes_nothing(page, scene):
    before = scene.read_bytes()
    page.click("[data-tool=walkable]")
    for u, v in [[200, 350], [400, 450], [400, 350], [200, 450]]:  # its edges cross
        _click(page, u, v)
    page.keyboard.press("Enter")
    _saved(page)
    message = page.inner_text("#message")
    assert page.get_attribute("#message", "class") == "error"
    assert message.startswith("not saved: ") and "layout.walkable" in message and "not simple" in message
    assert scene.read_bytes() == before and page.errors == [REFUSED]
    assert {path.name for path in scene.parent.iterdir()} == {"scene.yaml", "background.png"}


def test_figures_follow_the_mouse_with_their_height(page):
    page.mouse.move(*_screen(page, 480, 400))
    page.wait_for_selector("#figure-layer polyline")
    assert "1.5 m:" in page.inner_text("#ground") and "1.95 m:" in page.inner_text("#ground")


def test_measured_ground_points_refine_the_people_s_camera_in_a_real_browser(people_page, people_scene):
    truth = camera_of((960, 540), *PEOPLE_TRUTH.values())
    corners = [[150.0, 300.0], [820.0, 300.0], [200.0, 520.0], [760.0, 520.0]]
    measured = truth.ground_from_pixels(np.array(corners)).points[:, :2].round(2)
    before = people_page.inner_text("#camera")
    assert "5.85 m above the ground" in before
    people_page.click("[data-tool=point]")
    for (u, v), (x, y) in zip(corners, measured, strict=True):
        _click(people_page, u, v)
        people_page.fill("#prop-x", str(x))
        people_page.press("#prop-x", "Enter")
        people_page.fill("#prop-y", str(y))
        people_page.press("#prop-y", "Enter")
    assert people_page.locator("circle.ground-point").count() == 4
    _saved(people_page)
    assert "saved" in people_page.inner_text("#message") and people_page.errors == []
    points = np.array(yaml.safe_load(people_scene.read_text())["calibration"]["points"])
    assert points[:, :2] == pytest.approx(np.array(corners), abs=1.0)
    assert points[:, 2:] == pytest.approx(measured, abs=1e-6)
    pose = pose_of(load_scene(people_scene).camera)
    assert pose["height_m"] == pytest.approx(6.5, rel=0.03) and pose["tilt_deg"] == pytest.approx(25.0, abs=0.5)
    assert people_page.inner_text("#camera") != before  # the page shows the refined camera
