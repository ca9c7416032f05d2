#!/bin/bash
# One TUD-Stadtmitte compile, its facing model trained again alone and distilled from training seeds T..., every
# bundle's pose read against YOLO11n-pose @1280 in one process per half (run from this folder; the repository's
# environment): ./run.sh SCENE OUT COMPILE_SEED T...
set -e
SCENE=$1 OUT=$2 S=$3; shift 3
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
[ -f "$OUT/compile/bundle/manifest.json" ] || vc-compile "$SCENE" -o "$OUT/compile" --budget standard --seed "$S" --quiet
PYTHONPATH=$ROOT/src python train.py "$OUT/compile/renders" "$OUT/compile/bundle" "$OUT" "$@" >> results/train.jsonl
ARMS=("shipped=$OUT/compile/bundle")
for T in "$@"; do ARMS+=("single$T=$OUT/single$T/bundle" "distilled$T=$OUT/distilled$T/bundle"); done
for HALF in 0 1; do
  (cd "$ROOT" && PYTHONPATH=src python experiments/2026-12-02-keypoint-model-capacity/measure.py tud "$S" "$HALF" \
     "${ARMS[@]}") >> results/pose.jsonl
done
