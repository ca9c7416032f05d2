#!/bin/bash
# For each seed S given: the scene compiled as it ships (standard budget, --seed S) with the head map
# (--set train.head_map=true) into OUT/CAMERA$S, on the renders of the shipped compile SHIPPED$S (the same scene,
# seed and render settings render the same shards: they are hard-linked, not rendered again), then measured on both
# halves as results-as-shipped measures (measure.py) and its pose and time a frame against the shipped bundle, read
# in turn in one process (keypoint-model-capacity's measure.py), and read without the head map (centre_only.py); the
# last two not with POSE=0. Usage: [POSE=0] run.sh CAMERA SCENE
# SHIPPED OUT S... The shipped compile's facing and keypoint models, which a compile with the same renders and seed
# trains to the same bytes, may be copied into OUT/CAMERA$S/run first: the compile then keeps them.
set -e
CAMERA=$1 SCENE=$2 SHIPPED=$3 OUT=$4; shift 4
HERE=$(cd "$(dirname "$0")" && pwd); ROOT=$(cd "$HERE/../.." && pwd)
cd "$ROOT"; source .venv/bin/activate; export DRJIT_LIBLLVM_PATH=/usr/lib/x86_64-linux-gnu/libLLVM-19.so
for S in "$@"; do
  D=$OUT/$CAMERA$S
  mkdir -p "$D"
  [ -e "$D/renders" ] || cp -al "$SHIPPED$S/renders" "$D/renders"
  vc-compile "$SCENE" --budget standard --seed "$S" --set train.head_map=true -o "$D" --quiet
  (cd "$HERE" && PYTHONPATH=../../src python measure.py "$CAMERA" "$D/bundle" --seed "$S")
  [ "${POSE:-1}" = 0 ] && continue
  (cd "$HERE" && PYTHONPATH=../../src python centre_only.py "$CAMERA" "$D/bundle" --seed "$S")
  for HALF in 0 1; do  # a half whose line is written (its first frame: 1, or 91 / 201) is not run again
    FIRST=$([ $HALF = 0 ] && echo 1 || echo "\(91\|201\)")
    grep -q "\"seed\": $S, .*\"frames\": \[$FIRST, " "$HERE/results/pose_$CAMERA.jsonl" 2>/dev/null && continue
    PYTHONPATH=src python experiments/2026-12-02-keypoint-model-capacity/measure.py "$CAMERA" "$S" "$HALF" \
      "shipped=$SHIPPED$S/bundle" "head=$D/bundle" >> "$HERE/results/pose_$CAMERA.jsonl"
  done
done
