#!/bin/bash
# Each seed's facing model trained on long-haired renders, shipped in a copy of that seed's bundle, then its pose
# against the bundle's own on both halves (run from this folder): ./run.sh RUNS OUT CAMERA SCENE S...
# RUNS: the compiles (RUNS/CAMERA$S/bundle); OUT: where the renders and bundles go (not kept).
set -e
RUNS=$1 OUT=$2 CAMERA=$3 SCENE=$4; shift 4
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
for S in "$@"; do
  D=$OUT/$CAMERA$S
  mkdir -p "$D"
  [ -f results/facing_${CAMERA}_seed$S.json ] || PYTHONPATH=$ROOT/src python facing_long_hair.py "$SCENE" \
      "$RUNS/$CAMERA$S/bundle" "$D/renders" "$D/bundle" --seed "$S" --report results/facing_${CAMERA}_seed$S.json
done
for S in "$@"; do
  for HALF in 0 1; do
    (cd "$ROOT" && PYTHONPATH=src python experiments/2026-12-02-keypoint-model-capacity/measure.py "$CAMERA" "$S" \
       "$HALF" shipped="$RUNS/$CAMERA$S/bundle" long-hair="$OUT/$CAMERA$S/bundle") >> results/pose.jsonl
  done
done
