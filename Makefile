# Two entry points that set up their own environment (a .venv made here) on a fresh machine:
#   make luts   build the default LUTs into luts/
#   make test   run the test suite
#   make report error against run time (report/README.md and plots, about 70 s; installs the plot extra)
#   make materials  measured materials: the presets luts/materials.json, then report/materials.md (about 20 s)
#   make render     pictures: report/render/ (about 45 s)
#   make fidelity   basis fidelity: report/fidelity.md and its plot (validation groups, frontier, bounds, error vs K; about 2 minutes)
PYTHON ?= python3
VENV := .venv
STAMP := $(VENV)/.installed-stamp

.PHONY: luts test basis report materials render fidelity clean-venv

# what the shader tests run on: the GLSL/HLSL reference compiler, Mesa's software OpenGL with headless EGL and
# its software Vulkan driver (WebGPU's backend here)
SYSTEM_PACKAGES := glslang-tools libegl1 libegl-mesa0 libgl1-mesa-dri mesa-vulkan-drivers

$(STAMP): pyproject.toml
	@if [ "$$(id -u)" = 0 ] && command -v apt-get >/dev/null 2>&1; then \
		echo "installing $(SYSTEM_PACKAGES) (Debian)"; \
		DEBIAN_FRONTEND=noninteractive apt-get update -qq && \
		DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends $(SYSTEM_PACKAGES) >/dev/null; \
	else \
		echo "note: not root or no apt-get; the GPU shader tests need $(SYSTEM_PACKAGES) and skip without them"; \
	fi
	$(PYTHON) -m venv $(VENV)
	$(VENV)/bin/python -m pip install --quiet --upgrade pip
	$(VENV)/bin/python -m pip install --quiet -e '.[test,gpu]'
	touch $(STAMP)

luts: $(STAMP)
	$(VENV)/bin/fresnel-lut build --out luts

basis: $(STAMP)
	$(VENV)/bin/fresnel-lut basis --out luts/basis.json

report: $(STAMP)
	$(VENV)/bin/python -m pip install --quiet -e '.[test,plot]'
	$(VENV)/bin/fresnel-lut report --out report

materials: $(STAMP)
	$(VENV)/bin/fresnel-lut materials --presets luts/materials.json
	$(VENV)/bin/fresnel-lut report --materials --out report

fidelity: $(STAMP)
	$(VENV)/bin/fresnel-lut report --fidelity --out report

render: $(STAMP)
	$(VENV)/bin/fresnel-lut render --out report/render

test: $(STAMP)
	$(VENV)/bin/python -m pytest

clean-venv:
	rm -rf $(VENV)
