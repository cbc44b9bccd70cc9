# splatfill: the two commands in the README are `make demo` and `make test`; both set up what they need.
#
#   BLENDER=/path/to/blender   run Blender-side scripts through a real Blender instead of the bpy module
#   PYTHON=python3.11          the interpreter the two environments are made from (bpy 5.0.1 needs 3.11)

PYTHON ?= python3.11
BLENDER ?=
ENGINE := .venv/bin/python
BPY := .venv-blender/bin/python
DEMO ?= out/demo-$(shell date +%Y%m%d-%H%M%S)

ifeq ($(BLENDER),)
BLENDER_RUN = $(BPY)
BLENDER_ENV = .venv-blender/.ready
else
BLENDER_RUN = $(BLENDER) -b --factory-startup -P
BLENDER_ARGS_SEP = --
BLENDER_ENV =
endif

.PHONY: setup demo test lint
setup: .venv/.ready .venv-blender/.ready

.venv/.ready: requirements/engine.txt
	$(PYTHON) -m venv .venv
	$(ENGINE) -m pip install -q --upgrade pip
	$(ENGINE) -m pip install -q -r requirements/engine.txt
	touch $@

.venv-blender/.ready: requirements/blender.txt
	$(PYTHON) -m venv .venv-blender
	$(BPY) -m pip install -q --upgrade pip
	$(BPY) -m pip install -q -r requirements/blender.txt
	touch $@

# The main job. For now: generate a small livingroom scene and write a preview picture.
demo: .venv/.ready $(BLENDER_ENV)
	$(BLENDER_RUN) scripts/make_scene.py $(BLENDER_ARGS_SEP) --family livingroom --out $(DEMO)/scene \
		--views 24 --res 256 --samples 16
	$(ENGINE) -m engine preview --scene $(DEMO)/scene --out $(DEMO)/preview.png --rows 4
	@echo "scene: $(DEMO)/scene   preview: $(DEMO)/preview.png"

test: .venv/.ready .venv-blender/.ready lint
	$(ENGINE) -m pytest tests
	$(BPY) -m pytest tests/blender

lint: .venv/.ready
	$(ENGINE) -m ruff check .
