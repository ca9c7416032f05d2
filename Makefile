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

.PHONY: install test test-hard test-fast demo runtime-wheel lint clean

install: $(STAMP)

$(LLVM_LIB):
	@if [ "$$(id -u)" = 0 ]; then \
		apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq libllvm19; \
	else \
		sudo apt-get update -qq && sudo DEBIAN_FRONTEND=noninteractive apt-get install -y -qq libllvm19; \
	fi

$(STAMP): pyproject.toml packaging/runtime/pyproject.toml $(LLVM_LIB)
	test -x $(PY) || $(PYTHON) -m venv $(VENV)
	# torch first: the pinned CPU wheel; any looser spec pulls GBs of CUDA packages.
	$(PIP) install -q torch==2.13.0
	$(PIP) install -q -e '.[dev]'
	# COCO-C's corruptions, without the GUI OpenCV they ask for (pyproject.toml, the robustness extra)
	$(PIP) install -q --no-deps imagecorruptions-imaug==1.1.5
	touch $(STAMP)

test: install
	$(PY) -m pytest -q -n 2 --dist loadgroup

# The hard-case properties at 10 000 examples each (the default run draws 200): tests/hard_cases/.
test-hard: install
	VC_HARD_CASES=thorough $(PY) -m pytest -q -n 2 tests/hard_cases

# The inner loop while developing: skips tests marked slow (rendering).
test-fast: install
	$(PY) -m pytest -q -n 2 --dist loadgroup -m "not slow"

# The demo scene end to end: render its background from the layout with Mitsuba (the shipped PNG is this render),
# validate the scene and draw its region plan, then vc-compile it at the quick budget (~10 minutes on 2 cores:
# render synthetic people, train one ScenePoseNet per region, export the ONNX bundle, self-test it on full frames).
demo: install
	$(VENV)/bin/vc-scene synthesize examples/scenes/demo/scene.yaml -o $(DEMO_OUT)/background.png --spp 128
	$(VENV)/bin/vc-scene show examples/scenes/demo/scene.yaml -o $(DEMO_OUT)/regions.png
	$(VENV)/bin/vc-compile examples/scenes/demo/scene.yaml -o $(DEMO_OUT) --budget quick
	@echo "demo: the compiled detector on a demo frame: $(DEMO_OUT)/overlay.png (white: truth);" \
		"bundle $(DEMO_OUT)/bundle, stage record $(DEMO_OUT)/compile.json, region plan $(DEMO_OUT)/regions.png"

# The appliance runtime (numpy + onnxruntime only; extras video and signatures) as a wheel in dist/: packaging/runtime/.
runtime-wheel: install
	$(PY) packaging/runtime/build.py -o dist

lint: install
	$(VENV)/bin/ruff check .

clean:
	rm -rf $(VENV) out dist .pytest_cache .hypothesis
