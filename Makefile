# Two entry points that set up their own environment (a .venv made here) on a fresh machine:
#   make luts   build the default LUTs into luts/
#   make test   run the test suite
#   make report error against run time on this machine: build/report/README.md and plots (about 70 s; installs the
#               plot extra); the committed report/ is a snapshot with its commit and date: make report REPORT_OUT=report
#   make materials  measured materials: the presets luts/materials.json, then report/materials.md (about 20 s)
#   make render     pictures: report/render/ (about 45 s)
#   make view       the look-development page in your browser (fresnel-lut view --open, with the 'your asset' page:
#                   three.js from npm; Ctrl-C stops it)
#   make fidelity   basis fidelity: report/fidelity.md and its plot (validation groups, frontier, bounds, error vs K; about 2 minutes)
PYTHON ?= python3
VENV := .venv
STAMP := $(VENV)/.installed-stamp
TEST_STAMP := $(VENV)/.test-installed-stamp

.PHONY: luts test basis report materials render fidelity view clean-venv

# what the shader tests run on (only the test set-up installs them; building needs none): the GLSL/HLSL reference
# compiler, Mesa's software OpenGL with headless EGL and its software Vulkan driver (WebGPU's backend here), and
# Chromium for WebGL 2 (SwiftShader), driven by Playwright for Python (the 'browser' extra, no browser download), and
# Node.js with npm, which fetches the engines' packages the tests compare with by name and version (npm pack)
SYSTEM_PACKAGES := glslang-tools libegl1 libegl-mesa0 libgl1-mesa-dri mesa-vulkan-drivers chromium nodejs
# another process holding the dpkg lock (unattended upgrades, a second set-up) is waited for, not failed on
APT := DEBIAN_FRONTEND=noninteractive apt-get -o DPkg::Lock::Timeout=900 -o Acquire::Retries=3

$(STAMP): pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(VENV)/bin/python -m pip install --quiet --upgrade pip
	$(VENV)/bin/python -m pip install --quiet -e .
	touch $(STAMP)

$(TEST_STAMP): $(STAMP)
	@if [ "$$(id -u)" = 0 ] && command -v apt-get >/dev/null 2>&1; then \
		echo "installing $(SYSTEM_PACKAGES) (Debian)"; \
		for attempt in 1 2 3 4 5 6 7 8 9 10; do $(APT) update -qq && break; echo "apt-get update busy; retrying"; sleep 15; done; \
		$(APT) install -y -qq --no-install-recommends $(SYSTEM_PACKAGES) >/dev/null; \
		command -v npm >/dev/null || $(APT) install -y -qq --no-install-recommends npm >/dev/null; \
	else \
		echo "note: not root or no apt-get; the GPU and browser tests need $(SYSTEM_PACKAGES) and skip without them"; \
	fi
	$(VENV)/bin/python -m pip install --quiet -e '.[test,gpu,browser,materialx]'
	touch $(TEST_STAMP)

luts: $(STAMP)
	$(VENV)/bin/fresnel-lut build --ltc --pixel-tables --atlas --three --materialx --out luts

basis: $(STAMP)
	$(VENV)/bin/fresnel-lut basis --out luts/basis.json

# timings and dates differ on every run: by default they go to the ignored build/, not over the committed snapshot
REPORT_OUT ?= build/report
report: $(STAMP)
	$(VENV)/bin/python -m pip install --quiet -e '.[plot]'
	$(VENV)/bin/fresnel-lut report --out $(REPORT_OUT)

materials: $(STAMP)
	$(VENV)/bin/fresnel-lut materials --presets luts/materials.json
	$(VENV)/bin/fresnel-lut report --materials --out report

fidelity: $(STAMP)
	$(VENV)/bin/fresnel-lut report --fidelity --out report

render: $(STAMP)
	$(VENV)/bin/fresnel-lut render --out report/render

# the "your asset" page runs three.js as an application does: npm's three at the package's version, fetched once
THREE_VERSION = $$($(VENV)/bin/python -c "from handoff.three import THREE_VERSION; print(THREE_VERSION)")
view: $(STAMP)
	@mkdir -p build/npm && version=$(THREE_VERSION) && cd build/npm && if [ ! -f three-$$version/package/package.json ]; then \
		npm pack --silent three@$$version >/dev/null && mkdir -p three-$$version && tar xzf three-$$version.tgz -C three-$$version; fi
	$(VENV)/bin/fresnel-lut view --open --three-js build/npm/three-$(THREE_VERSION)/package

# the suite in three processes, the shader tests (Mesa in the process), the application's and the rest, so that none
# holds every part's memory at once: the largest process 0.81 GB instead of 1.29 GB in one (issue 26 item 17;
# /usr/bin/time -v bash .ci/run);
# every part runs even when an earlier one fails, and the target fails if any did
TEST_PARTS := tests/luts tests/fresnel_lut --ignore=tests/luts,--ignore=tests/fresnel_lut

test: $(TEST_STAMP)
	@status=0; for part in $(TEST_PARTS); do \
		echo "== pytest $$part" | tr ',' ' '; \
		$(VENV)/bin/python -m pytest $$(echo $$part | tr ',' ' ') || status=1; \
	done; exit $$status

clean-venv:
	rm -rf $(VENV)
