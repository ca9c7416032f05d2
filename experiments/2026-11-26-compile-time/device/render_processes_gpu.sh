#!/usr/bin/env bash
# Render throughput of several renderers sharing a lent GPU (the `device` tool): PETS09's render stage in one
# process, then in worker processes (`--executor processes`), in turn in one run, by
# `benchmarks/render_throughput.py --processes`. About 3 minutes of device time with the defaults.
# Needs .gpu/ (pack_gpu.sh) carried. Arguments go to render_throughput.py (default: --processes 12 --samples 400).
# Writes $OUT/render_throughput_processes.json and .md.
set -uo pipefail
root=$PWD
source "$(dirname "$0")/gpu_site.sh"
nvidia-smi --query-gpu=name,memory.total,driver_version --format=csv,noheader
echo "cpus: $(nproc)"
cd .gpu  # the checkout's own vc/ would shadow the installed package
args=("$@"); [ ${#args[@]} -gt 0 ] || args=(--processes 12 --samples 400)
python3 "$root/benchmarks/render_throughput.py" --scene pets09.yaml --out "$OUT" "${args[@]}" 2>&1 \
    | grep -v "shader binding table"
