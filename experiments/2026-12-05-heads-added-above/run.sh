#!/bin/bash
# Every threshold given, on both cameras' head-map compiles (head-map-as-shipped's, OUT/CAMERA$S/bundle), seeds 0-2.
# Usage: run.sh OUT THRESHOLD...
set -e
OUT=$1; shift
HERE=$(cd "$(dirname "$0")" && pwd)
cd "$HERE"; source ../../.venv/bin/activate
for T in "$@"; do
  for CAMERA in tud pets; do
    for S in 0 1 2; do
      PYTHONPATH=../../src python measure.py "$T" "$CAMERA" "$OUT/$CAMERA$S/bundle" --seed "$S"
    done
  done
done
