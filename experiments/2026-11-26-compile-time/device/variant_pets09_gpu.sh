#!/usr/bin/env bash
# A training variant measured against the compile it departs from, on one set of GPU renders: PETS09 compiled at
# standard on the lent GPU machine (compile_pets09_gpu.sh, 12 render processes), then its renders trained again
# with the variant's vc-train options and exported as the compile exports (int8 where it holds). Both bundles come
# back in $OUT (bundle.tar from the compile, variant.tar) for vc-eval on the real frames here; the pair shares
# renders and seed, so the difference is the variant's alone.
#
#   SEED=2 bash experiments/2026-11-26-compile-time/device/variant_pets09_gpu.sh --centre-offsets
#
# Needs .gpu/ (pack_gpu.sh). One call of the device tool: about 5 minutes of compile and 3 of variant on an H100.
set -uo pipefail
root=$PWD
seed=${SEED:-0}
LIMIT_S=${LIMIT_S:-400} bash "$(dirname "$0")/compile_pets09_gpu.sh" --executor processes --processes 12 \
    --seed "$seed" || exit 1
source "$(dirname "$0")/gpu_site.sh"
out=$root/out/gpu_pets09
[ -d "$out/bundle" ] || { echo "the compile did not finish: no variant"; exit 1; }
cd .gpu
start=$(date +%s)
python3 -c "$(vc_main train)" \
    "$out/renders" -o "$root/out/gpu_variant/run" --seed "$seed" --quiet "$@" 2>&1 | tee "$OUT/variant_train.log"
python3 -c "$(vc_main export)" \
    "$root/out/gpu_variant/run" -o "$root/out/gpu_variant/bundle" --precision auto --quiet 2>&1 \
    | tee "$OUT/variant_export.log"
echo "variant: $(( $(date +%s) - start )) s"
tar -cf "$OUT/variant.tar" -C "$root/out/gpu_variant" bundle run/metrics.json
