# Two commands do everything on a fresh machine: `make demo` and `make test` (both install first).
SHELL := /bin/bash
PYTHON ?= python3
VENV := .venv
PY := $(VENV)/bin/python
PIP := $(PY) -m pip
STAMP := $(VENV)/.installed
LLVM_LIB := /usr/lib/x86_64-linux-gnu/libLLVM-19.so
# Mitsuba's CPU backend must load LLVM 19: LLVM 15/16 abort on the first path-tracing kernel.
export DRJIT_LIBLLVM_PATH := $(LLVM_LIB)
DEMO_OUT ?= out/demo

.PHONY: install test test-fast demo lint clean

install: $(STAMP)

$(LLVM_LIB):
	@if [ "$$(id -u)" = 0 ]; then \
		apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq libllvm19; \
	else \
		sudo apt-get update -qq && sudo DEBIAN_FRONTEND=noninteractive apt-get install -y -qq libllvm19; \
	fi

$(STAMP): pyproject.toml $(LLVM_LIB)
	test -x $(PY) || $(PYTHON) -m venv $(VENV)
	# torch first: the pinned CPU wheel; any looser spec pulls GBs of CUDA packages.
	$(PIP) install -q torch==2.13.0
	$(PIP) install -q -e '.[dev,runtime]'
	touch $(STAMP)

test: install
	$(PY) -m pytest -q -n 2 --dist loadgroup

# The inner loop while developing: skips tests marked slow (rendering).
test-fast: install
	$(PY) -m pytest -q -n 2 --dist loadgroup -m "not slow"

# The demo scene end to end as far as the stages go today: render its background from the layout with
# Mitsuba, validate the scene and plan its regions, draw the overlay, render a labelled dataset of synthetic
# people (anny + Mitsuba) and a contact sheet of it, train a short ScenePoseNet per region (a few minutes; the
# full default budget is ~20 minutes per region, see the README), and export the ONNX bundle.
DEMO_STEPS ?= 200
demo: install
	$(VENV)/bin/vc-scene synthesize scenes/demo/scene.yaml -o $(DEMO_OUT)/background.png --spp 128
	$(VENV)/bin/vc-scene check scenes/demo/scene.yaml --json $(DEMO_OUT)/scene-check.json
	$(VENV)/bin/vc-scene show scenes/demo/scene.yaml -o $(DEMO_OUT)/overlay.png
	$(VENV)/bin/vc-render scenes/demo/scene.yaml -o $(DEMO_OUT)/renders --samples 300 --shard-size 100
	$(VENV)/bin/vc-render scenes/demo/scene.yaml --preview -o $(DEMO_OUT)/render-preview.png --samples 6
	$(VENV)/bin/vc-train $(DEMO_OUT)/renders -o $(DEMO_OUT)/run --steps $(DEMO_STEPS)
	$(VENV)/bin/vc-export $(DEMO_OUT)/run -o $(DEMO_OUT)/bundle
	@echo "demo: background $(DEMO_OUT)/background.png, overlay $(DEMO_OUT)/overlay.png," \
		"samples drawn in $(DEMO_OUT)/render-preview.png, held-out accuracy in $(DEMO_OUT)/run/metrics.json" \
		"and $(DEMO_OUT)/run/precision_recall.png, bundle in $(DEMO_OUT)/bundle"

lint: install
	$(VENV)/bin/ruff check .

clean:
	rm -rf $(VENV) out .pytest_cache .hypothesis
