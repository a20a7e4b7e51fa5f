# Set-up and everyday commands. `make demo` and `make test` work on a fresh machine:
# they install Mesa's EGL (only if missing), create .venv, install toonface into it, then run.
PYTHON ?= python3
VENV   := .venv
PY     := $(VENV)/bin/python
STAMP  := $(VENV)/.installed

.PHONY: all install system-deps browser demo lint test test-fast bench bench-deps docs pictures clean lipsync-model

all: test

system-deps:
	@scripts/ensure-system-deps.sh

# Chromium and chromedriver for the studio's browser tests, only if missing (they skip without).
browser:
	@scripts/ensure-browser.sh

# Re-installs only when the package metadata changed; a second run is a no-op.
$(STAMP): pyproject.toml requirements-faces.txt scripts/ensure-system-deps.sh
	@scripts/ensure-system-deps.sh
	@$(PYTHON) -c 'import sys; sys.exit(0 if sys.version_info >= (3, 11) else "toonface needs Python >= 3.11, found " + sys.version.split()[0])'
	@test -x $(PY) || $(PYTHON) -m venv $(VENV)
	@$(PY) -m pip install --quiet --disable-pip-version-check --upgrade pip
	@$(PY) -m pip install --quiet --disable-pip-version-check -e '.[test,faces,docs]'
	@$(PY) -m pip install --quiet --disable-pip-version-check --no-deps -r requirements-faces.txt
	@# Exactly one OpenCV, the headless contrib build: a GUI build installed by hand writes the same cv2/.
	@others=$$($(PY) scripts/other-opencv.py); if [ -n "$$others" ]; then \
		$(PY) -m pip uninstall --quiet -y $$others; \
		$(PY) -m pip install --quiet --disable-pip-version-check --force-reinstall --no-deps \
			"opencv-contrib-python-headless==$$($(PY) -c 'import importlib.metadata as m; print(m.version("opencv-contrib-python-headless"))')"; fi
	@touch $(STAMP)

install: $(STAMP)

demo: $(STAMP)
	$(VENV)/bin/toonface demo

# ruff and mypy are configured in pyproject.toml; `make test` runs both, so CI enforces them.
lint: $(STAMP)
	$(VENV)/bin/ruff check .
	$(VENV)/bin/mypy

# mypy (20 s from cold) checks beside the tests on the second core; its report shows only when it fails.
# Then every bench group once with --quick (about six minutes): a smoke test, not a measure, so that a
# group that raises fails the build (its figures are thrown away; its traceback shows).
test: $(STAMP) browser
	@$(VENV)/bin/ruff check .
	@log=$$(mktemp); $(VENV)/bin/mypy >$$log 2>&1 & pid=$$!; \
	$(PY) -m pytest; status=$$?; \
	if ! wait $$pid; then cat $$log; echo "mypy found type errors"; status=1; fi; rm -f $$log; \
	echo "python -m bench --quick (every group once, a smoke test)"; \
	$(PY) -m bench --quick >/dev/null || status=1; exit $$status

# both cores: the quick loop while working (make test, which CI runs, stays one process). Bytecode is
# written for the tests (this machine sets PYTHONDONTWRITEBYTECODE): pytest then keeps its rewritten
# test modules in __pycache__ instead of rewriting every assert of every module in each worker (12 s).
test-fast: $(STAMP)
	PYTHONDONTWRITEBYTECODE= $(PY) -m pytest -m 'not slow' -n 2

# The render bench's peers: skia-python, and pycairo built against Cairo's headers; the lip-sync bench's
# peer: Rhubarb Lip Sync 1.14.0 built from third_party/ into .bench/rhubarb (about two minutes, once).
bench-deps: $(STAMP)
	@dpkg -s libcairo2-dev pkg-config >/dev/null 2>&1 || { SUDO=$$([ "$$(id -u)" -ne 0 ] && echo sudo); \
		$$SUDO apt-get update -qq && $$SUDO apt-get install -y -qq --no-install-recommends libcairo2-dev pkg-config >/dev/null; }
	$(PY) -m pip install --quiet --disable-pip-version-check -e '.[bench]'
	@scripts/build-rhubarb.sh >/dev/null

bench: bench-deps
	$(PY) -m bench

# The voice's learned mouth (capture/voice_model.py): rebuilds data/models/voice_mouth.json bit for bit
# from the shared talking-face clips (../shared/realdata/video), seeded; a few minutes.
lipsync-model: $(STAMP)
	$(PY) -m bench.lipsync_train

# The documentation site (MkDocs) into site/; --strict: a broken link or a missing page fails it.
# make test builds it too (tests/test_docs.py).
docs: $(STAMP)
	NO_MKDOCS_2_WARNING=1 $(VENV)/bin/mkdocs build --strict

# Every picture of the site (docs/images/), from the project's own commands on the shared recordings.
pictures: $(STAMP) browser
	$(PY) scripts/docs-pictures.py

clean:
	rm -rf $(VENV) toonface-demo .pytest_cache *.egg-info site
