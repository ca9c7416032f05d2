"""``vc-scene edit``'s local web server: the editor page and the scene it edits (:mod:`vc.scenes.editor`).

Python's own HTTP server (``http.server``), bound to the loopback interface by default: one installer's browser on
the same machine, no internet, no dependency to install. The page is three files shipped in the package
(``editor_page/``): no external script, font or style, so it works on a site network with no way out.

Routes (JSON in and out; a bad edit is a 400 with the loader's message, which the page shows):

* ``GET /`` — the page; ``GET /editor.js``, ``/editor.css`` its script and style; ``GET /background`` the scene's
  background image;
* ``GET /api/state`` — the scene as saved, in pixels (:func:`vc.scenes.editor.page_state`);
* ``GET /api/figures?u=U&v=V`` — person figures of the prior's statures standing on the ground at pixel (U, V);
* ``POST /api/check`` — the region plan and grid an edit would give, nothing written;
* ``POST /api/save`` — the edit written to ``scene.yaml`` if it loads, else nothing written.

A fault in a request is logged and answered with a 500 naming it; the server keeps serving.
"""

from __future__ import annotations

import json
import logging
import mimetypes
import threading
from http import HTTPStatus
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer
from importlib import resources
from pathlib import Path
from urllib.parse import parse_qs, urlsplit

from vc.errors import InputError
from vc.scenes import editor
from vc.scenes.loader import load_scene

LOG = logging.getLogger("vc.scenes.editor")
#: The page's own files, served by name.
PAGE_FILES = {"/": "index.html", "/index.html": "index.html", "/editor.js": "editor.js", "/editor.css": "editor.css"}
#: The largest edit a page may post (bytes): a scene's layout is a few kilobytes.
MAX_BODY = 4 * 1024 * 1024


class EditorServer(ThreadingHTTPServer):
    """The server for one scene file; requests are answered one at a time (a lock), as one user edits one file."""

    daemon_threads = True

    def __init__(self, scene_path: Path, address: tuple[str, int]) -> None:
        self.scene_path = Path(scene_path).resolve()
        #: The scene as saved (loaded again after each save): a scene that does not load is refused before anything
        #: is served, and the figures under the mouse need its camera without reading the files again.
        self.scene = load_scene(self.scene_path)
        self.lock = threading.Lock()
        super().__init__(address, EditorHandler)

    @property
    def url(self) -> str:
        host, port = self.server_address[:2]
        return f"http://{host}:{port}/"


class EditorHandler(BaseHTTPRequestHandler):
    server: EditorServer

    def log_message(self, format: str, *args) -> None:  # noqa: A002 - the base class's name
        LOG.debug("%s " + format, self.address_string(), *args)

    def _send(self, status: int, body: bytes, content_type: str) -> None:
        self.send_response(status)
        self.send_header("Content-Type", content_type)
        self.send_header("Content-Length", str(len(body)))
        self.send_header("Cache-Control", "no-store")
        self.end_headers()
        self.wfile.write(body)

    def _json(self, status: int, data: object) -> None:
        self._send(status, json.dumps(data).encode(), "application/json")

    def _answer(self, work) -> None:
        try:
            with self.server.lock:
                self._json(HTTPStatus.OK, work())
        except InputError as error:
            self._json(HTTPStatus.BAD_REQUEST, {"error": str(error)})
        except Exception as error:  # a fault in one request must not stop the editor
            LOG.exception("request %s failed", self.path)
            self._json(HTTPStatus.INTERNAL_SERVER_ERROR, {"error": f"{type(error).__name__}: {error}"})

    def do_GET(self) -> None:  # noqa: N802 - http.server's name
        url = urlsplit(self.path)
        if url.path in PAGE_FILES:
            name = PAGE_FILES[url.path]
            body = resources.files("vc.scenes").joinpath("editor_page", name).read_bytes()
            self._send(HTTPStatus.OK, body, mimetypes.guess_type(name)[0] or "application/octet-stream")
        elif url.path == "/favicon.ico":  # browsers ask; the page has none
            self._send(HTTPStatus.NO_CONTENT, b"", "image/x-icon")
        elif url.path == "/background":
            self._answer_background()
        elif url.path == "/api/state":
            self._answer(lambda: editor.page_state(self.server.scene_path))
        elif url.path == "/api/figures":
            self._answer(lambda: self._figures(parse_qs(url.query)))
        else:
            self._json(HTTPStatus.NOT_FOUND, {"error": f"no such page: {url.path}"})

    def do_POST(self) -> None:  # noqa: N802 - http.server's name
        url = urlsplit(self.path)
        actions = {"/api/check": editor.preview, "/api/save": self._save}
        if url.path not in actions:
            self._json(HTTPStatus.NOT_FOUND, {"error": f"no such action: {url.path}"})
            return
        length = int(self.headers.get("Content-Length") or 0)
        if not 0 < length <= MAX_BODY:
            self._json(HTTPStatus.BAD_REQUEST, {"error": f"an edit is 1 to {MAX_BODY} bytes of JSON, got {length}"})
            return
        try:
            edit = json.loads(self.rfile.read(length))
        except ValueError as error:
            self._json(HTTPStatus.BAD_REQUEST, {"error": f"the edit is not JSON: {error}"})
            return
        if not isinstance(edit, dict):
            self._json(HTTPStatus.BAD_REQUEST, {"error": "the edit is a JSON object"})
            return
        self._answer(lambda: actions[url.path](self.server.scene_path, edit))

    def _save(self, scene_path: Path, edit: dict) -> dict:
        state = editor.save(scene_path, edit)
        self.server.scene = load_scene(scene_path)
        return state

    def _answer_background(self) -> None:
        try:
            image = self.server.scene.image_path
            body = image.read_bytes()
        except OSError as error:
            self._json(HTTPStatus.NOT_FOUND, {"error": str(error)})
            return
        self._send(HTTPStatus.OK, body, mimetypes.guess_type(image.name)[0] or "application/octet-stream")

    def _figures(self, query: dict) -> dict:
        try:
            u, v = float(query["u"][0]), float(query["v"][0])
        except (KeyError, ValueError):
            raise InputError(None, "figures", "give the pixel as ?u=U&v=V") from None
        scene = self.server.scene
        return editor.figures_at(scene.camera, (u, v), tuple(scene.priors.height_m))


def serve(scene_path: Path, host: str = "127.0.0.1", port: int = 0) -> EditorServer:
    """A server for ``scene_path`` bound to ``host``:``port`` (0: any free port), not yet serving: call
    ``serve_forever`` (or run it in a thread) and ``shutdown``."""
    return EditorServer(scene_path, (host, port))
