#!/bin/bash
# Per compile seed S: distil.py into OUT/CAMERA$S/bundle, then its pose against the compile's bundle, read in turn in
# one process, both halves (run from this folder; the repository's environment): ./distil.sh RUNS OUT CAMERA S...
set -e
RUNS=$1 OUT=$2 CAMERA=$3; shift 3
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
for S in "$@"; do
  [ -f "$OUT/$CAMERA$S/bundle/manifest.json" ] || PYTHONPATH=$ROOT/src python distil.py "$RUNS/$CAMERA$S/renders" \
      "$RUNS/$CAMERA$S/bundle" "$OUT/$CAMERA$S/bundle" --seed "$S" >> "results/distil_report_$CAMERA.jsonl"
  for HALF in 0 1; do
    (cd "$ROOT" && PYTHONPATH=src python experiments/2026-12-02-keypoint-model-capacity/measure.py "$CAMERA" "$S" \
       "$HALF" shipped="$RUNS/$CAMERA$S/bundle" distilled="$OUT/$CAMERA$S/bundle") >> "results/distilled_$CAMERA.jsonl"
  done
done
