#!/bin/bash
# Per compile seed S: rebuild.py into OUT/CAMERA$S/bundle, then that bundle's pose against the compile's, read in
# turn in one process (keypoint-model-capacity's measure.py), both halves (run from this folder; the repository's
# environment): ./rebuild.sh RUNS OUT CAMERA S...
set -e
RUNS=$1 OUT=$2 CAMERA=$3; shift 3
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
for S in "$@"; do
  [ -f "$OUT/$CAMERA$S/bundle/manifest.json" ] || PYTHONPATH=$ROOT/src python rebuild.py "$RUNS/$CAMERA$S/renders" \
      "$RUNS/$CAMERA$S/bundle" "$OUT/$CAMERA$S/bundle" --seed "$S"
done
for S in "$@"; do
  for HALF in 0 1; do
    (cd "$ROOT" && PYTHONPATH=src python experiments/2026-12-02-keypoint-model-capacity/measure.py "$CAMERA" "$S" \
       "$HALF" shipped="$RUNS/$CAMERA$S/bundle" members="$OUT/$CAMERA$S/bundle") >> "results/rebuilt_$CAMERA.jsonl"
  done
done
