"""A real RTSP server for vc-serve's tests: GStreamer's (gst-rtsp-server, the system packages'), streaming a folder
of JPEG frames as MJPEG over RTP at a given rate, like an IP camera.

    /usr/bin/python3 tests/serve_rtsp_server.py PORT FOLDER FPS      # rtsp://127.0.0.1:PORT/cam

Run by the system's Python, which has GStreamer's introspection bindings (python3-gi, gir1.2-gst-rtsp-server-1.0);
they are not on PyPI. Prints "ready" once it listens. Frames are FOLDER/00001.jpg, 00002.jpg, ...; each client that
connects while none is connected starts again at the first.
"""

import sys

import gi

gi.require_version("Gst", "1.0")
gi.require_version("GstRtspServer", "1.0")
from gi.repository import GLib, Gst, GstRtspServer  # noqa: E402 (after the versions are required)


def main() -> None:
    port, folder, fps = sys.argv[1], sys.argv[2], sys.argv[3]
    Gst.init(None)
    server = GstRtspServer.RTSPServer.new()
    server.set_service(port)
    factory = GstRtspServer.RTSPMediaFactory.new()
    # identity sync=true paces the frames at their timestamps (imagesequencesrc sets them at the rate)
    factory.set_launch(f"( imagesequencesrc location={folder}/%05d.jpg start-index=1 framerate={fps}/1 "
                       f"! jpegparse ! identity sync=true ! rtpjpegpay name=pay0 pt=26 )")
    factory.set_shared(True)
    server.get_mount_points().add_factory("/cam", factory)
    if server.attach(None) == 0:
        sys.exit(f"cannot listen on port {port}")
    print("ready", flush=True)
    GLib.MainLoop().run()


if __name__ == "__main__":
    main()
