# Two commands set up everything: `make run` and `make test`.
VENV ?= .venv
PYTHON ?= python3
PY := $(VENV)/bin/python
STAMP := $(VENV)/.installed

.PHONY: run test bench clean screenshots kernels

# The environment is made without pip (ensurepip's copy is old, slow to install and slow to
# resolve with); the interpreter's pip puts the current pip into it (`pip --python`, pip 22.3 or
# newer; otherwise ensurepip's copy is used). What the compiled kernels need (numpy, numba,
# pygame: their pyproject lines) is installed first, so that the kernels build on the idle core
# while pip downloads and unpacks the rest (pip works on one core); with scipy and PyYAML, which
# the benches' build (bench.motions, MOP's take fits) imports. Byte-code is written after
# each step on every core, the packages' own test suites left out, from the machine's cache of
# compiled code (tabletop/bytecode_cache.py, ~/.cache/tabletop/bytecode: a fresh clone's
# 3,571 modules compiled by compileall 20-24 CPU s, from the cache 3.5).
KERNEL_DEPS = $$(sed -n 's/^ *"\(\(numpy\|numba\|pygame-ce\|scipy\|PyYAML\)[^"]*\)".*/\1/p' pyproject.toml)
$(STAMP): pyproject.toml
	test -x $(PY) || $(PYTHON) -m venv --without-pip $(VENV)
	$(PY) -m pip --version >/dev/null 2>&1 \
	  || $(PYTHON) -m pip --python $(PY) install --quiet --no-compile pip \
	  || $(PY) -m ensurepip >/dev/null
	$(PY) -m pip install --quiet --no-compile $(KERNEL_DEPS)
	$(PY) -m tabletop.bytecode_cache -x '/tests?/' $(VENV)/lib
	( $(BUILD_KERNELS) ) & kernels=$$!; \
	$(PY) -m pip install --quiet --no-compile -e '.[test]' \
	  && $(PY) -m tabletop.bytecode_cache -x '/tests?/' $(VENV)/lib; \
	status=$$?; wait $$kernels || rm -f $(KERNELS); exit $$status
	$(PY) -c "from tabletop import early_stop as e; e.write_site_line()" && touch $(EARLY_STOP)
	touch $(STAMP)

# A stop signal while the interpreter itself starts (`site`, the editable install's finder: the
# first 20-60 ms of every command) is the same clean stop as later (one line, status 130, no
# traceback): a .pth line runs tabletop/early_stop.py there (an environment made before it has
# it added by `make run`, `make test` or `make kernels`).
EARLY_STOP := $(VENV)/.early-stop
$(EARLY_STOP): | $(STAMP)
	$(PY) -c "from tabletop import early_stop as e; e.write_site_line()" && touch $@

# The compiled kernels (numba: MOP's, Puppet Master's searches and step, the view's drawing) are
# built once, into the cache, so neither the installation's first start nor each test worker
# compiles them: during the install, and again (a few seconds, from the cache) when a file of
# theirs changes. The three builds run side by side (about 50-80 s of CPU cold in all). The
# cache (behaviors/kernel_cache.py: every kernel is built through it) is ~/.cache/tabletop/kernels,
# one folder per contents of their files, shared by every clone on the machine: a fresh clone
# (CI's) then only loads them (the three builds 5.3 CPU s; 36.5 when 26 of them were cached
# beside their sources by numba's own cache).
KERNELS := $(VENV)/.kernels
# (MOP's threshold model is compiled on its first call: a follower takes a few steps; the kernels
# declared with a signature load on first need, behaviors/kernel_cache.py: all are built here)
MOP_STEPS = import numpy as np, behaviors.mop.window_kernel, behaviors.mop.group_kernel, behaviors.mop.members, \
	behaviors.mop.member_validity, behaviors.mop.sharing; \
	from behaviors.mop.follower import ActionFollower; \
	f = ActionFollower({'a': np.c_[np.linspace(0, 0.3, 30), np.zeros(30)]}, invariance='scale'); \
	[f.step(np.array([0.01 * i, 0.0])) for i in range(40)]; \
	from behaviors.kernel_cache import load, PENDING; load(*PENDING)
# (with the Puppet Master's, the benchmarks' path alignment, bench.motions.aligned_gap, that the
# MOP tests' unrelated motions call: else the test workers compiled it on first use, 0.8 s each;
# and MOP's take fits, behaviors/mop/take_fit.py, on gestures followed at two sizes: else every
# test worker and installation started on a fresh clone compiled them on first use, 2-5 CPU s.
# scipy and PyYAML, which these import, are installed with the kernels' own packages)
PM_AND_BENCH = import numpy as np, behaviors.puppet_master.search_kernel, \
	behaviors.puppet_master.step_kernel, behaviors.puppet_master.match_step_kernel, \
	bench.motions; \
	bench.motions.aligned_gap(np.zeros((2, 2)), np.ones((3, 2))); \
	from bench.follow_quality import puck_follower, run; \
	g = bench.motions.gesture_templates(); f = puck_follower(g); rng = np.random.default_rng(0); \
	[run(f, bench.motions.performance(rng, g[n], s)[0]) \
	 for n in ('circle', 'zigzag') for s in (0.7, 1.4)]; \
	from behaviors.kernel_cache import load, PENDING; load(*PENDING)
BUILD_KERNELS = \
	$(PY) -c "from tabletop.drawing import raster, dirty, halo_kernel, pose_kernel, outline_kernel; [m.warm() for m in (raster, dirty, halo_kernel, pose_kernel, outline_kernel)]" & view=$$!; \
	$(PY) -c "$(PM_AND_BENCH)" & pm=$$!; \
	$(PY) -c "$(MOP_STEPS)" && wait $$view && wait $$pm && touch $(KERNELS) \
	&& { $(PY) -m behaviors.kernel_prune || true; }
# (kernel_prune then removes old versions of them from ~/.cache/tabletop/kernels: kept are the
# last three of each kernel and any used within a week; the kernels built stand if it fails)
# (make decides before the install runs: the test skips a build the install has just made)
KERNEL_SOURCES = behaviors/kernel_cache.py tabletop/drawing/*.py behaviors/mop/*.py \
	behaviors/puppet_master/*.py bench/motions.py
$(KERNELS): $(wildcard $(KERNEL_SOURCES)) | $(STAMP)
	@test -f $@ -a -z "$$(find $^ -newer $@ 2>/dev/null)" \
	  || { echo "building the compiled kernels"; $(BUILD_KERNELS); }

kernels: $(KERNELS) $(EARLY_STOP)

run: $(STAMP) kernels
	$(VENV)/bin/tabletop run --config config.yaml $(ARGS)

# The suite runs in TEST_WORKERS worker processes (pytest-xdist): four on the two-core target
# machine, so that one worker's waits (live runs, sockets, `tabletop` subprocesses) are another's
# CPU time (quiet machine, 2,136 tests: 231 s against 252-270 s with three; with 2,000 tests
# three took 167 s against 195-212 s with two). A worker that runs out of tests
# takes half of another's queue. The project's byte-code (the benches' and tests' helpers too)
# is compiled first: the many `tabletop` subprocesses of the tests then load it, not the sources.
# So are pytest's rewritten test modules (tests/rewritten.py), on every core: each worker imports
# them all, and rewriting their asserts was two thirds of its collection (9.5 -> 2.8 CPU s);
# with the pytest plugins' modules, which each process rewrote again (1.0 -> 0.25 CPU s). The
# test modules' plain byte-code is left out: pytest imports their rewritten form only (that
# step 2.1-2.5 -> 1.5 CPU s on a fresh clone). Both are kept in the machine's cache of byte-code
# (tabletop/bytecode_cache.py): only the files changed since it last saw them are compiled.
TEST_WORKERS ?= 4
test: $(STAMP) kernels
	$(PY) -m tabletop.bytecode_cache -x '/(test_[^/]*|conftest)\.py$$' tabletop behaviors \
	  tracking calibration bench tests
	$(PY) -m tests.rewritten
	$(PY) -m pytest -n $(TEST_WORKERS) --dist worksteal

# Every benchmark script in turn (`python -m bench`, bench/__main__.py), each one's last line;
# exits 1 naming those that failed. BENCHES="bench/osc.py bench/view.py" runs only those. The
# soaks (bench/*soak.py: the 20-minute real-time gallery soak, the simulated hour, the
# follower's 200,000 steps) run only with SOAKS=1 (`make bench SOAKS=1`) or when named.
BENCHES ?=
SOAKS ?=
bench: $(STAMP)
	$(PY) -m bench $(if $(SOAKS),--soaks) $(BENCHES)

clean:
	rm -rf $(VENV) build *.egg-info

# README pictures, made by the installation itself (headless runs with snapshots).
screenshots: $(STAMP)
	$(PY) -m tabletop.screenshots --out docs/screenshots
