#!/bin/bash
# Per compile seed S: two more facing models on its renders (training seeds 1000+S and 2000+S), then its bundle read
# with the three averaged, both halves (run from this folder): ./run.sh RUNS OUT CAMERA S...
# RUNS: the compiles (RUNS/CAMERA$S/{renders,bundle}); OUT: where the models go (not kept).
set -e
RUNS=$1 OUT=$2 CAMERA=$3; shift 3
for S in "$@"; do
  PYTHONPATH=../../src python train_more.py "$RUNS/$CAMERA$S/renders" "$OUT/$CAMERA$S" $((1000 + S)) $((2000 + S))
done
for S in "$@"; do
  for HALF in 0 1; do
    PYTHONPATH=../../src python measure.py "$CAMERA" "$S" "$HALF" "$RUNS/$CAMERA$S/bundle" \
      "$OUT/$CAMERA$S/seed$((1000 + S))/facing.onnx" "$OUT/$CAMERA$S/seed$((2000 + S))/facing.onnx" \
      >> "results/same_renders_$CAMERA.jsonl"
  done
done
