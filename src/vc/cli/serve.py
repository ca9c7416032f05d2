"""``vc-serve``: run bundles on live cameras until stopped.

    vc-serve CONFIG.yaml [--log-level info]

CONFIG names the cameras (each a bundle and a source: rtsp://, http(s):// MJPEG, a video file, a folder of images,
/dev/videoN), the MQTT broker, the on-disk event queue and the health server (:mod:`vc.serve.config`; the format
is in docs/serve.md). Tracked people are published as ``new``/``update``/``end`` events to
``<topic_prefix>/<camera>/events``; ``/healthz`` and ``/metrics`` are served over HTTP. SIGTERM or SIGINT stops it
cleanly (exit status 0): the frame in flight is finished and every event not yet acknowledged by the broker stays
in the queue for the next start. A bad configuration or bundle prints one ``error:`` line naming the file and the
field and exits with status 2, before anything starts.
"""

from __future__ import annotations

import argparse
import logging
import signal
from pathlib import Path

from vc import __version__
from vc.cli.common import handles_input_errors
from vc.serve.config import read_serve_config
from vc.serve.service import Service


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="vc-serve", description=__doc__.split("\n\n")[0])
    parser.add_argument("--version", action="version", version=f"%(prog)s {__version__}")
    parser.add_argument("config", type=Path, help="the service's configuration (YAML)")
    parser.add_argument("--log-level", choices=("debug", "info", "warning", "error"), default="info")
    return parser


@handles_input_errors
def main(argv: list[str] | None = None) -> int:
    args = _parser().parse_args(argv)
    logging.basicConfig(level=args.log_level.upper(), format="%(asctime)s %(levelname)s %(message)s", force=True)
    service = Service(read_serve_config(args.config))
    for signum in (signal.SIGTERM, signal.SIGINT):
        signal.signal(signum, lambda *_: service.stop())
    print(f"vc-serve: {len(service.workers)} camera(s), health and metrics on http://{service.config.http.host}:"
          f"{service.port}/healthz and /metrics, events to {service.config.mqtt.host}:{service.config.mqtt.port}",
          flush=True)
    service.run()
    print(f"vc-serve: stopped; {service.queue.depth} event(s) kept in {service.queue.path} for the next start",
          flush=True)
    return 0
