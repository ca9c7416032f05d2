#!/bin/bash
# For each seed S given: r0 of compile PREFIX$S (e.g. /work/runs/tudm0) trained again with a head map and a size map in two of its
# fine centre maps (0036's "one network", head-beside-centre's train_both.py), exported int8 into a copy of that
# compile's run, then measured on both halves. Usage: [REGIONS="r0 r1"] run.sh CAMERA SCENE PREFIX OUT S...
# (REGIONS: the regions trained again, r0 by default; with more, the bundle is OUT/CAMERA$S/bundle_all, its run
# run_all, and measure_heads.py reads it with --all as arms centre_only_all and head_all).
set -e
while pgrep -f train_both.py > /dev/null; do sleep 20; done  # a training left running by an earlier call
CAMERA=$1 SCENE=$2 PREFIX=$3 OUT=$4; shift 4
HERE=$(cd "$(dirname "$0")" && pwd); ROOT=$(cd "$HERE/../.." && pwd)
cd "$ROOT"; source .venv/bin/activate; export DRJIT_LIBLLVM_PATH=/usr/lib/x86_64-linux-gnu/libLLVM-19.so
OLD=$ROOT/experiments/2026-12-01-head-beside-centre
for S in "$@"; do
  C=$PREFIX$S D=$OUT/$CAMERA$S
  REGIONS=${REGIONS:-r0}; [ "$REGIONS" = r0 ] && ALL="" || ALL=_all
  mkdir -p "$D"
  for R in $REGIONS; do
    # the trainer resumes from its last checkpoint (none left to do once it has finished)
    (cd "$OLD" && PYTHONPATH=../..:../../src python train_both.py "$C/run" "$C/renders" $R -o "$D/train")
  done
  if [ ! -f "$D/bundle$ALL/manifest.json" ]; then
    rm -rf "$D/run$ALL" && cp -r "$C/run" "$D/run$ALL"
    for R in $REGIONS; do cp "$D/train/checkpoints/$R.pt" "$D/run$ALL/checkpoints/$R.pt"; done
    ln -sfn "$C/renders" "$D/renders"  # the run names its renders relative to itself
    vc-export "$D/run$ALL" -o "$D/bundle$ALL" --scene "$SCENE" --precision int8 --eval-samples 0
  fi
  (cd "$HERE" && PYTHONPATH=../..:../../src:../2026-12-01-head-beside-centre:../2026-12-01-visible-anchor \
     python measure_heads.py "$CAMERA" "$S" "$D/bundle$ALL" ${ALL:+--all})
done
