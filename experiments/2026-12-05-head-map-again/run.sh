#!/bin/bash
# For each seed S given: r0 of compile PREFIX$S (e.g. /work/runs/tudm0) trained again with a head map and a size map in two of its
# fine centre maps (0036's "one network", head-beside-centre's train_both.py), exported int8 into a copy of that
# compile's run, then measured on both halves. Usage: run.sh CAMERA SCENE PREFIX OUT S...
set -e
while pgrep -f train_both.py > /dev/null; do sleep 20; done  # a training left running by an earlier call
CAMERA=$1 SCENE=$2 PREFIX=$3 OUT=$4; shift 4
HERE=$(cd "$(dirname "$0")" && pwd); ROOT=$(cd "$HERE/../.." && pwd)
cd "$ROOT"; source .venv/bin/activate; export DRJIT_LIBLLVM_PATH=/usr/lib/x86_64-linux-gnu/libLLVM-19.so
OLD=$ROOT/experiments/2026-12-01-head-beside-centre
for S in "$@"; do
  C=$PREFIX$S D=$OUT/$CAMERA$S
  mkdir -p "$D"
  # the trainer resumes from its last checkpoint (none left to do once it has finished)
  (cd "$OLD" && PYTHONPATH=../..:../../src python train_both.py "$C/run" "$C/renders" r0 -o "$D/train")
  if [ ! -f "$D/bundle/manifest.json" ]; then
    rm -rf "$D/run" && cp -r "$C/run" "$D/run" && cp "$D/train/checkpoints/r0.pt" "$D/run/checkpoints/r0.pt"
    ln -sfn "$C/renders" "$D/renders"  # the run names its renders relative to itself
    vc-export "$D/run" -o "$D/bundle" --scene "$SCENE" --precision int8 --eval-samples 0
  fi
  (cd "$HERE" && PYTHONPATH=../..:../../src:../2026-12-01-head-beside-centre:../2026-12-01-visible-anchor \
     python measure_heads.py "$CAMERA" "$S" "$D/bundle")
done
