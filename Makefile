# The two set-up commands of the README:
#   make study   installs the engines (Debian packages) and the Python venv, runs the study
#   make test    installs the same, runs the tests
# Both work as root and, otherwise, through sudo (only apt-get needs it).
SHELL := /bin/bash
VENV := .venv
PY := $(VENV)/bin/python
SUDO := $(shell [ "$$(id -u)" = 0 ] || echo sudo)
DEBIAN_PACKAGES := liggghts yade lammps python3-venv python3-pip
JOBS ?= 2

.PHONY: study test bench engines venv clean ci-study

study: engines venv
	$(VENV)/bin/snakemake -j$(JOBS) all

# Two workers (pytest-xdist): the end-to-end workflow tests mostly wait on short processes.
test: engines venv
	$(PY) -m pytest -n $(JOBS) --dist loadgroup

bench: engines venv
	OMP_NUM_THREADS=1 taskset -c 0 $(PY) -m benchmarks.reference_solver
	$(PY) -m benchmarks.study
	OMP_NUM_THREADS=1 taskset -c 0 $(PY) -m benchmarks.calibration_coverage

# The DEM engines come from Debian's packages; skip apt when they are already there.
engines:
	@if command -v liggghts >/dev/null && command -v yade >/dev/null && command -v lmp >/dev/null && python3 -c 'import venv, ensurepip' 2>/dev/null; then \
	  echo "engines: liggghts, yade and lammps are installed"; \
	else \
	  $(SUDO) apt-get update && \
	  $(SUDO) env DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends $(DEBIAN_PACKAGES); \
	fi

venv: $(VENV)/.installed

$(VENV)/.installed: pyproject.toml
	python3 -m venv $(VENV)
	$(PY) -m pip install --quiet --upgrade pip
	$(PY) -m pip install --quiet -e '.[test]'
	@# Compile the reference solver's numba kernel once here (cache=True), not in every first job.
	$(PY) -c 'from reference import solve_collision; solve_collision(0.1)'
	touch $@

clean:
	rm -rf results .snakemake

# CI's reduced study: one material, three K, both engines, both geometries.
ci-study: engines venv
	$(VENV)/bin/snakemake -j$(JOBS) all --config cases=cases/steel.yaml 'K_grid=[0.01,0.1,0.2]'
