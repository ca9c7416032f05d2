"""vc-serve's parts on their own: its configuration refused by file and field, the on-disk event queue, tracks as
events, zones and ground positions, and the reader's one-frame slot. The service against real servers:
tests/test_serve_live.py."""

from __future__ import annotations

import json
import sqlite3
import threading
import time

import numpy as np
import pytest
from serve_factory import marker_bundle

from vc.cli.serve import main as vc_serve
from vc.deploy.bundle import load_bundle
from vc.deploy.runtime import Person
from vc.deploy.zones import SceneZones, Zone
from vc.errors import InputError
from vc.serve.config import read_serve_config
from vc.serve.events import TrackEvents
from vc.serve.queue import EventQueue
from vc.serve.sources import CameraReader, CapturedFrame, LatestFrame


def _config(tmp_path, text: str, bundle=None):
    (tmp_path / "frames").mkdir(exist_ok=True)
    path = tmp_path / "serve.yaml"
    path.write_text(text.replace("BUNDLE", str(bundle or tmp_path)))
    return path


GOOD = """
cameras:
  - name: gate
    bundle: BUNDLE
    source: frames
    fps: 5
"""


def test_a_configuration_resolves_paths_beside_itself_and_takes_the_defaults(tmp_path, bundle):
    config = read_serve_config(_config(tmp_path, GOOD, bundle))
    camera = config.cameras[0]
    assert camera.source == str(tmp_path / "frames") and camera.bundle == bundle
    assert config.events.queue == tmp_path / "events.sqlite" and config.mqtt.port == 1883
    assert config.stale_after_s(camera) == 2 * camera.reading.read_timeout_s


@pytest.mark.parametrize(("text", "field", "reason"), [
    (GOOD.replace("fps: 5", "fps: 5\n    colour: red"), "cameras.0.colour", "unknown field"),
    ("mqtt: {port: 1883}\n", "cameras", "missing required field"),
    (GOOD.replace("fps: 5", ""), "cameras.0.fps", "a folder of images is played at a rate"),
    (GOOD.replace("source: frames", "source: missing.avi"), "cameras.0.source", "not found"),
    (GOOD.replace("bundle: BUNDLE", "bundle: nowhere"), "cameras.0.bundle", "not found"),
    (GOOD + GOOD.replace("cameras:\n", ""), "(top level)", "camera names must be unique: gate repeated"),
    (GOOD.replace("name: gate", "name: gate/1"), "cameras.0.name", "String should match pattern"),
    (GOOD + "mqtt: {port: 99999}\n", "mqtt.port", "less than or equal to 65535"),
    (GOOD + "events: {queue_limit: 0}\n", "events.queue_limit", "greater than or equal to 1"),
    (GOOD.replace("fps: 5", "fps: 5\n    unfit: hide"), "cameras.0.unfit", "'hide' is not one of"),
    (GOOD.replace("fps: 5", "fps: 5\n    engine: tensorrt"), "cameras.0.engine", "'tensorrt' is not one of"),
    ("cameras: [\n", "line", "not valid YAML"),
])
def test_a_bad_configuration_is_one_line_naming_the_file_and_field_and_exit_status_2(tmp_path, bundle, capsys,
                                                                                    text, field, reason):
    path = _config(tmp_path, text, bundle)
    assert vc_serve([str(path)]) == 2
    error = capsys.readouterr().err.strip()
    assert error.count("\n") == 0 and error.startswith(f"error: {path}: {field}") and reason in error
    assert not (tmp_path / "events.sqlite").exists()  # refused before anything started


def test_a_damaged_bundle_is_refused_before_the_service_starts(tmp_path, bundle, capsys):
    damaged = marker_bundle(bundle, tmp_path / "damaged")
    (damaged / "models" / "r0.onnx").write_bytes(b"not a model")
    assert vc_serve([str(_config(tmp_path, GOOD, damaged))]) == 2
    assert "model" in capsys.readouterr().err and not (tmp_path / "events.sqlite").exists()


def test_the_queue_keeps_order_across_a_restart_and_drops_the_oldest_beyond_its_bound(tmp_path):
    queue = EventQueue(tmp_path / "q.sqlite", limit=5)
    dropped = [queue.push("t", json.dumps({"n": n})) for n in range(8)]
    assert dropped == [0] * 5 + [1] * 3 and queue.dropped == 3 and queue.depth == 5
    kept = queue.oldest(10)
    assert [json.loads(event.payload)["n"] for event in kept] == [3, 4, 5, 6, 7]
    queue.remove(kept[1].sequence)
    queue.close()
    again = EventQueue(tmp_path / "q.sqlite", limit=5)  # a restart finds what was not acknowledged, in order
    assert [json.loads(event.payload)["n"] for event in again.oldest(10)] == [3, 5, 6, 7] and again.depth == 4
    assert [json.loads(event.payload)["n"] for event in again.oldest(2, after=kept[2].sequence)] == [6, 7]
    again.push("t", "{}")
    assert again.oldest(10)[-1].sequence > kept[-1].sequence  # sequences never repeat, even after removals
    again.close()


def test_a_queue_file_that_is_not_a_database_is_refused_by_name(tmp_path):
    (tmp_path / "q.sqlite").write_text("a text file")
    with pytest.raises(InputError, match="q.sqlite: not a usable event queue"):
        EventQueue(tmp_path / "q.sqlite", limit=5)


def test_pushes_from_several_threads_all_arrive(tmp_path):
    queue = EventQueue(tmp_path / "q.sqlite", limit=10_000)
    threads = [threading.Thread(target=lambda k=k: [queue.push("t", f"{k}-{n}") for n in range(100)])
               for k in range(4)]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    assert queue.depth == 400 and len({event.payload for event in queue.oldest(1000)}) == 400
    rows = sqlite3.connect(tmp_path / "q.sqlite").execute("SELECT COUNT(*) FROM events").fetchone()[0]
    assert rows == 400  # committed, as another process sees it
    queue.close()


def _person(track: int, foot: tuple[float, float], coasted: bool = False) -> Person:
    x, y = foot
    return Person("r0", 0.9, np.array([x - 5, y - 30, x + 5, y]), np.zeros((17, 3)), np.zeros((1, 1), bool), (0, 0),
                  track=track, coasted=coasted)


def _events(zones=()):
    camera = load_bundle_camera()
    return TrackEvents("gate", SceneZones(camera, list(zones)), update_interval_s=1.0, confirm_observations=3)


def load_bundle_camera() -> dict:
    """A camera 10 m above the ground looking straight down (ground x, y = image x, y / 100 about the centre)."""
    return {"size": [200, 200], "K": [[1000.0, 0, 99.5], [0, 1000.0, 99.5], [0, 0, 1]],
            "distortion": {"model": "none"}, "R": [[1, 0, 0], [0, -1, 0], [0, 0, -1]], "t": [0, 0, 10]}


def test_a_track_is_announced_once_seen_three_times_and_updated_at_most_once_a_second():
    events = _events()
    kinds = []
    for k in range(12):  # 5 frames a second
        kinds.append([e["type"] for e in events.update([_person(7, (100, 100))], {7}, k * 0.2, 1e9 + k * 0.2, k + 1)])
    assert kinds[:2] == [[], []] and kinds[2] == ["new"]
    assert [k for k, found in enumerate(kinds) if found == ["update"]] == [7]  # 1 s after the new, at frame 8
    ended = events.update([], set(), 3.0, 1e9 + 3, 13)
    assert [e["type"] for e in ended] == ["end"] and ended[0]["reason"] == "unseen"
    assert ended[0]["duration_s"] == pytest.approx(2.2) and ended[0]["frame"] == 12  # last seen at frame 12


def test_a_track_seen_fewer_times_makes_no_events_at_all():
    events = _events()
    assert events.update([_person(3, (50, 50))], {3}, 0.0, 0.0, 1) == []
    assert events.update([], set(), 1.5, 1.5, 2) == [] and events.tracks == {}


def test_events_carry_ground_metres_and_zones_entered_and_left_at_once():
    door = Zone("door", "image", ((90, 90), (130, 90), (130, 130), (90, 130)))  # pixels
    lawn = Zone("lawn", "ground", ((-1.0, -1.0), (0.02, -1.0), (0.02, 1.0), (-1.0, 1.0)))  # metres: u < 101.5 px
    events = _events([door, lawn])
    made = []
    for k, x in enumerate([60, 70, 80, 100, 101, 102, 140]):  # 0.1 s apart: within the update interval
        made += events.update([_person(1, (x, 100))], {1}, k * 0.1, k * 0.1, k + 1)
    made += events.end_all(1.0, "shutdown")
    assert [(e["type"], e["zones"], e["entered"], e["left"]) for e in made] == [
        ("new", ["lawn"], ["lawn"], []), ("update", ["door", "lawn"], ["door"], []),
        ("update", ["door"], [], ["lawn"]), ("update", [], [], ["door"]), ("end", [], [], [])]
    assert made[0]["ground_m"] == pytest.approx([-0.195, -0.005], abs=1e-6) and made[0]["frame"] == 3
    assert made[-1]["reason"] == "shutdown" and len({e["id"] for e in made}) == len(made)


def test_feet_above_the_horizon_have_no_ground_point_and_are_in_no_ground_zone():
    camera = {"size": [200, 200], "K": [[200.0, 0, 99.5], [0, 200.0, 99.5], [0, 0, 1]],
              "distortion": {"model": "none"}, "R": [[1, 0, 0], [0, 0, -1], [0, 1, 0]], "t": [0, 1.5, 0]}
    everywhere = Zone("all", "ground", ((-1e3, -1e3), (1e3, -1e3), (1e3, 1e3), (-1e3, 1e3)))
    zones = SceneZones(camera, [everywhere])  # level camera 1.5 m up: the horizon is the middle row
    ground = zones.ground_points(np.array([[99.5, 49.5], [99.5, 149.5]]))
    assert np.isnan(ground[0]).all() and ground[1] == pytest.approx([0.0, 6.0], abs=1e-6)
    assert zones.zones_at(np.array([[99.5, 49.5], [99.5, 149.5]]), ground) == [[], ["all"]]


@pytest.mark.parametrize(("zones", "field"), [
    ("door", "zones"), ([{"frame": "image", "polygon": [[0, 0], [1, 0], [1, 1]]}], "zones.0"),
    ([{"name": "a", "frame": "sky", "polygon": [[0, 0], [1, 0], [1, 1]]}], "zones.0.frame"),
    ([{"name": "a", "frame": "image", "polygon": [[0, 0], [1, 0]]}], "zones.0.polygon"),
    ([{"name": "a", "frame": "image", "polygon": [[0, 0], [1, 0], [1, 1]]}] * 2, "zones.1.name"),
])
def test_a_bundle_with_a_malformed_zone_is_refused_by_name(bundle, tmp_path, zones, field):
    copy = marker_bundle(bundle, tmp_path / "zoned", zones=zones)
    with pytest.raises(InputError, match=f"manifest.json: {field}"):
        load_bundle(copy)


def test_the_slot_keeps_only_the_latest_frame_and_counts_the_ones_it_replaced():
    slot = LatestFrame()
    frames = [CapturedFrame(n, np.zeros((1, 1, 3), np.uint8), 0.0, float(n)) for n in range(1, 4)]
    assert [slot.put(frame) for frame in frames] == [False, True, True]
    assert slot.take(0.1).number == 3 and slot.dropped == 2 and slot.take(0.01) is None


def test_a_reader_refuses_frames_of_another_size_and_names_it(bundle, tmp_path):
    import cv2

    from vc.serve.config import CameraSettings

    (tmp_path / "frames").mkdir()
    for n in range(3):
        cv2.imwrite(str(tmp_path / "frames" / f"{n}.png"), np.zeros((32, 48, 3), np.uint8))
    camera = CameraSettings(name="gate", bundle=bundle, source=str(tmp_path / "frames"), fps=100)
    counted = []
    reader = CameraReader(camera, (128, 64), counted.append)
    reader.start()
    reader.join(timeout=10)
    status = reader.snapshot()
    assert status.state == "finished" and status.frames_read == 0 and status.frames_refused == 3
    assert status.last_error == "frames of 48x32, the bundle's camera is 128x64: not run"
    assert counted == ["refused"] * 3 and reader.latest.take(0.01) is None


def test_a_stream_that_does_not_open_is_retried_with_growing_waits(bundle):
    from vc.serve.config import CameraSettings, ReadingSettings

    camera = CameraSettings(name="gate", bundle=bundle, source="rtsp://127.0.0.1:9/none",
                            reading=ReadingSettings(open_timeout_s=0.5, backoff_initial_s=0.1, backoff_max_s=0.4))
    reader = CameraReader(camera, (128, 64))
    reader.start()
    time.sleep(2.0)
    reader.stop()
    reader.join(timeout=5)
    status = reader.snapshot()
    # waits 0.1, 0.2, 0.4, 0.4 ... after refused connections: a handful of tries in 2 s, not hundreds
    assert 2 <= status.reconnects <= 8 and status.state == "disconnected" and "cannot open" in status.last_error


def test_a_scenes_zones_travel_into_its_bundle_and_leave_its_content_hash_alone(tmp_path, bundle):
    from scene_factory import write_scene

    from vc.model.export import with_zones
    from vc.scenes.loader import load_scene

    plain_path = write_scene(tmp_path / "plain")
    plain = load_scene(plain_path)
    zoned_path = write_scene(tmp_path / "zoned")  # the same scene, zones added in the middle of the file
    text = zoned_path.read_text()
    middle = text.index("regions:")
    zones = ("zones:\n- name: kiosk-queue\n  polygon: [[-4, 6], [-2, 6], [-2, 7], [-4, 7]]\n"
             "- {name: door, frame: image, polygon: [[10, 10], [60, 10], [60, 90]]}\n")
    zoned_path.write_text(text[:middle] + zones + text[middle:])
    zoned = load_scene(zoned_path)
    # zones change nothing rendered or trained: a bundle takes them at export, without a new compile
    assert zoned.content_hash == plain.content_hash and plain.zones == ()
    manifest = json.loads((bundle / "manifest.json").read_text())
    copy = marker_bundle(bundle, tmp_path / "zoned_bundle", zones=with_zones(manifest, zoned)["zones"])
    loaded = load_bundle(copy)
    assert [(zone.name, zone.frame) for zone in loaded.zones] == [("kiosk-queue", "ground"), ("door", "image")]
    assert with_zones(manifest, plain) is manifest  # no zones: the manifest as it was


def test_a_frames_result_says_how_long_its_networks_and_their_decoding_took(bundle, tmp_path):
    from serve_factory import marker_frame

    from vc.deploy.runtime import Runtime

    with Runtime(marker_bundle(bundle, tmp_path / "markers"), threads=1) as runtime:
        result = runtime.run(marker_frame((128, 64), [(5, 8)]))
    assert len(result.people) == 1 and result.network_s > 0 and result.decode_s > 0  # the service's histograms


def test_a_looped_one_image_folder_is_played_at_its_rate_not_as_fast_as_it_reads(bundle, tmp_path, caplog):
    import logging

    import cv2

    from vc.serve.config import CameraSettings

    (tmp_path / "frames").mkdir()
    cv2.imwrite(str(tmp_path / "frames" / "only.png"), np.zeros((64, 128, 3), np.uint8))
    camera = CameraSettings(name="gate", bundle=bundle, source=str(tmp_path / "frames"), fps=20, loop=True)
    reader = CameraReader(camera, (128, 64))
    with caplog.at_level(logging.INFO, logger="vc.serve"):
        reader.start()
        time.sleep(1.0)
        reader.stop()
        reader.join(timeout=5)
    assert 15 <= reader.snapshot().frames_read <= 25  # 20 frames a second, across the loop's restarts
    # its opening is logged once, not at every restart
    assert sum("reading" in record.getMessage() for record in caplog.records) == 1


def test_a_camera_that_stops_showing_its_scene_says_so_in_its_health_log_and_metrics(bundle, tmp_path, caplog):
    import logging

    import cv2

    from vc.deploy.bundle import MANIFEST
    from vc.deploy.fitness import SceneReference
    from vc.model.export import with_reference, write_bundle
    from vc.serve.health import ServiceMetrics
    from vc.serve.service import SETTLED_FRAMES, CameraWorker, EventSink

    rng = np.random.default_rng(3)
    texture = [cv2.GaussianBlur(rng.normal(0, 1, (64, 128, 3)).astype(np.float32), (0, 0), sigma) for sigma in (2, 8)]
    view = np.clip(128 + sum(40 * part / part.std() for part in texture), 0, 255).astype(np.uint8)  # a scene
    manifest = json.loads((bundle / MANIFEST).read_text())
    files = {path.relative_to(bundle).as_posix(): path.read_bytes() for path in bundle.rglob("*")
             if path.is_file() and path.name != MANIFEST}
    decode = (np.arange(256, dtype=np.float32) / 255) ** 2.2
    manifest, files = with_reference(manifest, files, SceneReference.of_background(view, decode), "a test view")
    write_bundle(manifest, files, tmp_path / "referenced", as_zip=False)
    config = read_serve_config(_config(tmp_path, GOOD, tmp_path / "referenced"))
    metrics = ServiceMetrics()
    worker = CameraWorker(config.cameras[0], load_bundle(tmp_path / "referenced"), config,
                          EventSink(config, EventQueue(tmp_path / "queue.db", 100), metrics), metrics)
    moved = np.ascontiguousarray(np.pad(view, ((0, 0), (5, 0), (0, 0)), mode="edge")[:, :128])  # 5 px to the right
    frames = [view] * 3 + [np.zeros_like(view)] * 2 + [view] * 2 + [np.zeros_like(view)] * SETTLED_FRAMES \
        + [view] * SETTLED_FRAMES + [moved] * SETTLED_FRAMES
    states = []
    with caplog.at_level(logging.INFO, logger="vc.serve"):
        for number, image in enumerate(frames, 1):
            worker.process(CapturedFrame(number, image, time.time(), float(number)))
            states.append(worker.health(float(number))["scene"]["state"])
    # the first frame settles at once; two black frames are a blip, five a covered camera, told once, then back
    assert states[:7] == ["ok"] * 7 and states[7 + SETTLED_FRAMES - 2] == "ok"
    assert states[7 + SETTLED_FRAMES - 1] == "covered" and states[-1] == "ok"
    scene = worker.health(float(len(frames)))["scene"]
    assert scene["registered_px"] == [5, 0] and scene["registered_roll_deg"] is None and scene["for_s"] >= 0
    messages = [(record.levelname, record.getMessage()) for record in caplog.records]
    told = [(level, message) for level, message in messages if "scene" in message]
    assert len(told) == 3 and told[0] == ("INFO", "camera gate: scene ok") and told[2] == ("INFO",
                                                                                          "camera gate: scene ok again")
    assert told[1][0] == "WARNING" and told[1][1].startswith("camera gate: scene covered (no scene")
    assert ("WARNING", "camera gate: the view is moved (5, 0) px from the background's, and compensated") in messages
    exposition = metrics.exposition().decode()
    assert 'vc_frames_fitness_total{camera="gate",state="covered"} 7.0' in exposition
    worker.runtime.close()
