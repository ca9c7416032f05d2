#!/bin/bash
# Every bundle, both halves, into results/arms.jsonl (run from the repository root): ./run.sh RUNS
set -e
here=experiments/2026-12-05-each-person-own-part
for camera in tud pets; do
  for seed in 0 1 2; do
    for which in 0 1; do
      PYTHONPATH=src python $here/measure.py $camera $seed $which "$1/$camera$seed/bundle" >> $here/results/arms.jsonl
    done
  done
done
