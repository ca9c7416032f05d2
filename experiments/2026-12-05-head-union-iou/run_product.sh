#!/bin/bash
# The decoder as main has it, on every head-map bundle, into results/ARM (run from this folder): ./run_product.sh RUNS ARM
set -e
for camera in tud pets; do
  for seed in 0 1 2; do
    PYTHONPATH=../../src python -c "
import sys
from pathlib import Path
sys.argv = ['measure.py', '$camera', '$1/$camera$seed/bundle', '--seed', '$seed']
import importlib.util
spec = importlib.util.spec_from_file_location('shipped_measure', '../2026-12-05-results-as-shipped/measure.py')
measure = sys.modules['shipped_measure'] = importlib.util.module_from_spec(spec)
spec.loader.exec_module(measure)
measure.RESULTS = Path('results/$2')
measure.main()
"
  done
done
