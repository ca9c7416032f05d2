#!/bin/bash
# The camera rolled about the frame's centre, measured by the robustness benchmark with the runtime that reads and
# undoes a roll (ROOT: this change's checkout) and with the one before it (BASE: a checkout of d36b786 with this
# change's benchmarks/robustness.py copied in): PETS09 dev frames every 10th and TUD-Stadtmitte every 4th, seed 0
# bundles as shipped, YOLO11n-pose @1280 in the same run.  Usage: run.sh ROOT BASE PETS_BUNDLE TUD_BUNDLE OUT
set -euo pipefail
ROOT=$1 BASE=$2 PETS_BUNDLE=$3 TUD_BUNDLE=$4 OUT=$5
P=$ROOT/../shared/data/pets09_s2l1 T=$ROOT/../shared/data/tud_stadtmitte Y=$ROOT/../shared/baselines/yolo11n-pose-1280.onnx
TUD_BACKGROUND=${TUD_BACKGROUND:?the TUD-Stadtmitte scene background (vc-scene init of its frames)}
for arm in read:$ROOT before:$BASE; do
  name=${arm%%:*} tree=${arm#*:}
  for degrees in 0.25 0.5 1 -1 2 3; do
    (cd "$tree" && PYTHONPATH=$tree/src:$tree python -m benchmarks.robustness "$PETS_BUNDLE" --video $P/vtest.avi \
       --gt $P/gt_dev_frames_0001-0400.txt --frames 1:400:10 --background $P/background.png --external $Y \
       --corruptions --conditions roll --roll $degrees --threads 2 --quiet --out "$OUT/$name/pets09_$degrees")
    (cd "$tree" && PYTHONPATH=$tree/src:$tree python -m benchmarks.robustness "$TUD_BUNDLE" --video $T/frames \
       --gt $T/gt_world.txt --frames 1:179:4 --background "$TUD_BACKGROUND" --external $Y \
       --corruptions --conditions roll --roll $degrees --threads 2 --quiet --out "$OUT/$name/tud_$degrees")
  done
done
