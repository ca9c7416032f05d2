#!/usr/bin/env bash
# PETS09 standard compile on a lent GPU machine (the `device` tool), timed beside the CPU compiles.
#
# The device machine reaches no package registry and has its own Python (3.12, torch with CUDA), so what the
# compile needs beyond that image travels in `.gpu/` (git-ignored, carried; made by pack_gpu.sh): the project and
# its missing dependencies as one pruned site-packages archive, anny's model cache (built here, so that anny's
# warp kernels, a 150 MB wheel, are not needed there), and the scene with its background and video.
# Resumable: the compile keeps its finished stages in out/gpu_pets09 (ignored; kept while the machine stays warm),
# so a call cut at its time limit is continued by running this again at once. Arguments go to vc-compile (e.g.
# `--executor processes --processes 12`: the render shards in 12 worker processes sharing the GPU).
set -uo pipefail
root=$PWD
source "$(dirname "$0")/gpu_site.sh"
nvidia-smi --query-gpu=name,memory.total,driver_version --format=csv,noheader
echo "cpus: $(nproc)"; ls /usr/local/nvidia/lib64 2>/dev/null | grep -i -E "optix|libcuda.so" | head -3
cd .gpu  # the checkout's own vc/ would shadow the installed package
python3 -c "import drjit as dr, torch; print('drjit cuda', dr.has_backend(dr.JitBackend.CUDA), 'torch', torch.__version__, torch.cuda.is_available())"
out=$root/out/gpu_pets09
start=$(date +%s)
# stopped before the call's limit (SIGINT: the compile keeps what it finished), so that the lines below still run
timeout -s INT "${LIMIT_S:-530}" python3 -c \
    "$(vc_main compile)" \
    pets09.yaml -o "$out" --budget standard --seed 0 "$@" 2>&1 \
    | tee -a "$OUT/compile.log" | tr '\r' '\n' | grep -v -E "^\s*$|it/s\]|step/s\]|sample/s\]|s/it\]"
echo "this call: $(( $(date +%s) - start )) s"
cp "$out"/compile.json "$OUT"/ 2>/dev/null
[ -d "$out/bundle" ] && tar -cf "$OUT/bundle.tar" -C "$out" bundle
ls "$out"
