#!/usr/bin/env bash
# Put a scene of one's own into .gpu/NAME/ for the device scripts (after pack_gpu.sh): its YAML, background and
# calibration, and of its video only the frames a compile measures (render/camera_measurements.py
# measured_frames), as a folder of PNGs in the same order, so that the measurements, and with them the renders,
# are those of the whole video. The video must be a folder of images (a video file travels whole: pack_gpu.sh).
#
#   bash experiments/2026-11-26-compile-time/device/pack_scene_gpu.sh path/to/tud/scene.yaml tud   # then SCENE=tud/scene.yaml
set -euo pipefail
scene=$1 name=$2
[ -d .gpu ] || { echo "no .gpu/: run experiments/2026-11-26-compile-time/device/pack_gpu.sh first"; exit 1; }
rm -rf ".gpu/$name" && mkdir -p ".gpu/$name/frames"
python3 - "$scene" ".gpu/$name" <<'EOF'
import shutil
import sys
from pathlib import Path

import yaml

from vc.deploy.frames import FrameSource
from vc.render.camera_measurements import measured_frames
from vc.scenes.loader import load_scene

scene, target = load_scene(Path(sys.argv[1])), Path(sys.argv[2])
if scene.video_path is None or not scene.video_path.is_dir():
    sys.exit(f"{scene.path}: video must be a folder of frames here")
source = FrameSource(scene.video_path, measured_frames(scene.video_path))
for number, file in enumerate(source.files, start=1):
    if number in source.frames:
        shutil.copy(file, target / "frames" / file.name)
text = yaml.safe_load(scene.path.read_text())
folder = scene.path.parent
shutil.copy(folder / text["image"], target / Path(text["image"]).name)
text["image"] = Path(text["image"]).name
calibration = text["calibration"]["path"]
shutil.copy(folder / calibration, target / Path(calibration).name)
text["calibration"]["path"] = Path(calibration).name
text["video"] = "frames"
(target / "scene.yaml").write_text(yaml.safe_dump(text, sort_keys=False))
EOF
du -sh ".gpu/$name" .gpu
