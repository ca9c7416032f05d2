#!/bin/bash
# Every arm on every head-map bundle (run from this folder): ./run.sh RUNS IOU...
set -e
runs=$1; shift
for iou in "$@"; do
  for camera in tud pets; do
    for seed in 0 1 2; do
      PYTHONPATH=../../src python measure.py "$iou" $camera "$runs/$camera$seed/bundle" --seed $seed
    done
  done
done
