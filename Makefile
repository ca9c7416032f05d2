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

# Debian packages: gcc for the C decoder (and its sanitizers); LLVM 19 for Mitsuba's CPU backend; for vc-serve's tests
# a real MQTT broker (mosquitto) and a real RTSP camera (GStreamer's RTSP server, run by the system Python through its introspection bindings: tests/serve_*);
# chromium for vc-scene edit's browser test (Playwright drives it; it cannot download its own browser here).
SYSTEM_PACKAGES := gcc libllvm19 chromium mosquitto python3-gi gir1.2-gstreamer-1.0 gir1.2-gst-rtsp-server-1.0 gstreamer1.0-rtsp \
	gstreamer1.0-plugins-base gstreamer1.0-plugins-good gstreamer1.0-plugins-bad
SUDO := $(if $(filter 0,$(shell id -u)),,sudo)

.PHONY: install system-packages test test-hard test-fast demo runtime-wheel lint clean

# The C decoder (src/vc/deploy/native/, vc.deploy.native), built with gcc (its sanitizers too, for the tests).
NATIVE := src/vc/deploy/native
NATIVE_LIB := $(NATIVE)/libvc_decode.so

install: system-packages $(STAMP) $(NATIVE_LIB)

# Installs only what is missing (dpkg -s answers in milliseconds when all are there).
system-packages:
	@dpkg -s $(SYSTEM_PACKAGES) >/dev/null 2>&1 || { $(SUDO) apt-get update -qq && \
		$(SUDO) env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq $(SYSTEM_PACKAGES); }

$(STAMP): pyproject.toml packaging/runtime/pyproject.toml | system-packages
	test -x $(PY) || $(PYTHON) -m venv $(VENV)
	# torch first: the pinned CPU wheel; any looser spec pulls GBs of CUDA packages.
	$(PIP) install -q torch==2.13.0
	$(PIP) install -q -e '.[dev]'
	# COCO-C's corruptions, without the GUI OpenCV they ask for (pyproject.toml, the robustness extra)
	$(PIP) install -q --no-deps imagecorruptions-imaug==1.1.5
	touch $(STAMP)

$(NATIVE_LIB): $(wildcard $(NATIVE)/vc_*.c $(NATIVE)/vc_*.h) | $(STAMP)
	$(PY) -m vc.deploy.native

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
