#!/usr/bin/env bash
# Training variants of one scene on one set of GPU renders: the scene rendered once at the standard budget's
# 2 000 samples per region (12 render processes; rendered once per machine: kept for later calls while it stays
# warm), then trained once per variant (each argument is one variant's
# vc-train options; "" for the defaults), two variants at a time, and each exported as a compile exports (int8
# where it holds). The bundles come back in $OUT/variants.tar (v0/bundle, v0/run/metrics.json, ...; logs/variants.txt
# says which is which) for vc-eval on the real frames here. The variants share renders and seed, so their differences
# are theirs alone. TRAIN_SEED (default SEED) trains them again with another seed on the same renders.
#
#   SCENE=tud/scene.yaml SEED=1 bash experiments/2026-11-26-compile-time/device/variants_gpu.sh "" "--centre-offsets" \
#       "--centre-offsets --offset-weight 0.3"
#
# SCENE is relative to .gpu/ (pack_gpu.sh; a scene of your own goes beside it with its background, calibration
# and the video frames its effects are measured from). Stops what is unfinished at LIMIT_S (default 540) and
# still returns what finished.
set -uo pipefail
root=$PWD
seed=${SEED:-0}
train_seed=${TRAIN_SEED:-$seed}  # another training seed on the same renders (a call after the first, machine warm)
deadline=$(( $(date +%s) + ${LIMIT_S:-540} ))
source "$(dirname "$0")/gpu_site.sh"
cd .gpu  # the checkout's own vc/ would shadow the installed package
out=$root/out/variants
runs=$out/train_seed_$train_seed logs=$out/train_seed_$train_seed/logs
mkdir -p "$logs"
vc() { local tool=$1; shift; timeout -s INT $(( deadline - $(date +%s) )) python3 -c "$(vc_main "$tool")" "$@"; }
start=$(date +%s)
vc render "$SCENE" -o "$out/renders" --samples "${SAMPLES:-2000}" --seed "$seed" --processes 12 --quiet \
    > "$logs/render.log" 2>&1 || { tail -5 "$logs/render.log"; exit 1; }
echo "render: $(( $(date +%s) - start )) s"
variant() {  # index, vc-train options
    local name=v$1 started; started=$(date +%s); shift
    # shellcheck disable=SC2086  # the options are words
    vc train "$out/renders" -o "$runs/$name/run" --seed "$train_seed" --workers 6 --quiet $1 \
        > "$logs/$name.train.log" 2>&1 \
        && vc export "$runs/$name/run" -o "$runs/$name/bundle" --precision auto --quiet > "$logs/$name.export.log" 2>&1
    local status=$?
    echo "$name ($1): $(( $(date +%s) - started )) s, exit $status"
}
index=0
for options in "$@"; do
    echo "v$index $options" >> "$logs/variants.txt"
    variant "$index" "$options" &
    index=$(( index + 1 ))
    (( index % 2 == 0 )) && wait
done
wait
echo "all: $(( $(date +%s) - start )) s"
# one file: the tool brings back only a few
cd "$runs" && tar -cf "$OUT/variants.tar" logs v*/bundle v*/run/metrics.json v*/run/r*/training_loss.png 2>/dev/null
