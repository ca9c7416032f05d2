#!/usr/bin/env bash
# A short device check (about 2 minutes of a lent GPU): PETS09 samples rendered with Mitsuba's cuda_ad_rgb, to
# compare with the same samples rendered here on the CPU from the same scene file (`vc-render .gpu/pets09.yaml -o DIR
# --samples 20`; a sample's draws follow from the scene file's bytes), by compare_renders.py. Each sample's
# people, light, noise and ray seeds come from its index, so the two backends must agree up to float rounding;
# the OptiX fault of 2026-11-26 (compile_gpu_pets09.md) put 1.4-1.6 % of r0/r1 pixels more than 2 levels off.
# Needs .gpu/ (pack_gpu.sh) carried. Writes $OUT/renders.tar (the samples) and $OUT/render.log.
set -uo pipefail
source "$(dirname "$0")/gpu_site.sh"
cd .gpu  # the checkout's own vc/ would shadow the installed package
rm -rf /tmp/gpu-renders
python3 -c "$(vc_main render)" \
    pets09.yaml -o /tmp/gpu-renders --samples "${SAMPLES:-20}" --quiet 2>&1 | tee "$OUT/render.log" \
    | grep -v "shader binding table" ; grep -c "shader binding table" "$OUT/render.log" | sed 's/^/OptiX warnings: /'
tar -cf "$OUT/renders.tar" -C /tmp gpu-renders
