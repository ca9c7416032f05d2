"""PETS09 served live (frozen experiment, issue 58): does ``vc-serve`` deliver, through a real RTSP camera and a real
MQTT broker, the people ``vc-run`` finds in the same frames, and at what accuracy?

PETS09 frames FIRST-LAST are written as JPEG (quality 95) and streamed by GStreamer's RTSP server (the tests' camera,
``tests/serve_rtsp_server.py``) at 7 frames/s, PETS09's rate; ``vc-serve`` runs the bundle on the stream and publishes
to mosquitto (``update_interval_s: 0``: every frame of a track is an event), a subscriber keeps every event. ``vc-run``
runs the same bundle on the same JPEG files, tracked at 7 frames/s. Compared, frame by frame: the people served (``new``
and ``update`` events, not carried) against the people ``vc-run`` reports (not carried, of tracks seen 3 times: a track
is announced from then on), boxes matched at IoU 0.5, and both against the ground truth (AP50 of the served people,
scores as served; ``vc-run``'s announced people the same way). Writes ``OUT/serve_on_pets.json``.

    PYTHONPATH=.:tests python experiments/2026-11-29-serve-on-pets/serve_on_pets.py BUNDLE -o OUT [--frames 1:400]
"""

from __future__ import annotations

import argparse
import json
import time
from collections import defaultdict
from pathlib import Path

import cv2
import numpy as np
from serve_servers import Broker, RtspCamera, Service, Subscriber, wait

from vc.cli.run import main as vc_run
from vc.cores import cpu_facts
from vc.deploy.boxes import box_iou
from vc.deploy.frames import FrameRange, FrameSource
from vc.evaluation.metrics import ImageResult, evaluate
from vc.evaluation.mot import read_mot_boxes

DATA = Path(__file__).resolve().parents[2].parent / "shared" / "data" / "pets09_s2l1"
FPS = 7


def matched(served: list[list[float]], expected: list[list[float]]) -> int:
    """How many served boxes match an expected box at IoU 0.5, one to one, greedily by IoU."""
    if not served or not expected:
        return 0
    iou = box_iou(np.array(served, np.float64), np.array(expected, np.float64))
    count = 0
    while iou.size and iou.max() >= 0.5:
        row, column = np.unravel_index(int(np.argmax(iou)), iou.shape)
        iou[row, :], iou[:, column] = -1, -1
        count += 1
    return count


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("bundle", type=Path)
    parser.add_argument("-o", "--out", type=Path, required=True)
    parser.add_argument("--frames", default="1:400")
    args = parser.parse_args()
    first, last = (int(part) for part in args.frames.split(":"))
    out = args.out
    frames = out / "frames"
    frames.mkdir(parents=True, exist_ok=True)
    for index, frame in enumerate(FrameSource(DATA / "vtest.avi", FrameRange(first, last, 1)), start=1):
        cv2.imwrite(str(frames / f"{index:05d}.jpg"), frame.image[:, :, ::-1], [cv2.IMWRITE_JPEG_QUALITY, 95])
    count = last - first + 1

    broker = Broker(out / "broker")
    broker.start()
    camera = RtspCamera(frames, fps=FPS)
    subscriber = Subscriber(broker.port)
    service = Service(out, args.bundle, camera.url, broker.port, events={"update_interval_s": 0})
    try:
        camera.start()
        service.start()
        started = time.monotonic()
        # the stream ends after its last frame and is opened again: the first run through is the one compared
        health = wait(lambda: (lambda c: c if c["reconnects"] >= 1 else None)(service.camera()), count / FPS + 60,
                      "the stream's end", step_s=0.5)
        streamed_s = time.monotonic() - started
        assert service.terminate() == 0
        made = service.events()
        wait(lambda: len(subscriber.received()) == len(made), 30, "every event at the subscriber")
        received = subscriber.received()
    finally:
        subscriber.close()
        camera.kill()
        broker.stop()

    assert vc_run([str(args.bundle), str(frames), "-o", str(out / "run"), "--fps", str(FPS), "--quiet"]) == 0
    expected, expected_scores, seen = {}, {}, defaultdict(int)
    for line in (out / "run" / "detections.jsonl").read_text().splitlines():
        frame = json.loads(line)
        people = [person for person in frame["people"] if not person["coasted"]]
        for person in people:
            seen[person["track"]] += 1
        announced = [person for person in people if seen[person["track"]] >= 3]
        expected[frame["frame"]] = [person["box"] for person in announced]
        expected_scores[frame["frame"]] = [person["score"] for person in announced]
    served, scores = defaultdict(list), defaultdict(list)
    for event in received:
        if event["type"] != "end" and not event["carried"] and event["frame"] <= count:
            served[event["frame"]].append(event["box"])
            scores[event["frame"]].append(event["score"])
    frames_served = sorted(served)
    agreeing = sum(matched(served[number], expected.get(number, [])) for number in expected)
    truth = read_mot_boxes(DATA / "gt_dev_frames_0001-0400.txt")
    images = [ImageResult(truth.get(first + number - 1, np.zeros((0, 4))), np.array(served[number]).reshape(-1, 4),
                          np.array(scores[number], np.float64)) for number in range(1, count + 1)]
    images_run = [ImageResult(truth.get(first + number - 1, np.zeros((0, 4))),
                              np.array(expected.get(number, [])).reshape(-1, 4),
                              np.array(expected_scores.get(number, []), np.float64)) for number in range(1, count + 1)]
    report = {
        "machine": cpu_facts()[0], "bundle": args.bundle.name, "frames": {"first": first, "last": last},
        "fps": FPS, "streamed_s": round(streamed_s, 1),
        "health_at_the_stream_end": {key: health[key] for key in ("frames_read", "frames_run", "frames_dropped",
                                                                  "frames_refused", "reconnects")},
        "events": {"made": len(made), "received": len(received),
                   "received_in_order_once": [e["id"] for e in received] == [e["id"] for e in made],
                   "by_type": {kind: sum(e["type"] == kind for e in made) for kind in ("new", "update", "end")}},
        "frames_with_people_served": len(frames_served),
        "people": {"vc_run": sum(len(boxes) for boxes in expected.values()),
                   "served": sum(len(boxes) for boxes in served.values()), "served_matching_vc_run": agreeing},
        "ap50_served_against_truth": round(evaluate(images).ap50, 4),
        "ap50_vc_run_announced_against_truth": round(evaluate(images_run).ap50, 4),
    }
    (out / "serve_on_pets.json").write_text(json.dumps(report, indent=1))
    print(json.dumps(report, indent=1))


if __name__ == "__main__":
    main()
