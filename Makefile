# swarm_forage: `make demo` and `make test` work on a fresh Debian 12 machine (they install what is missing).
SHELL := /bin/bash
.ONESHELL:
.SHELLFLAGS := -eo pipefail -c

ROOT := $(CURDIR)
WS := $(ROOT)/.ws
# The test fixtures' workspace over $(WS): controller plugins that fail on purpose, for the tests only, so that
# no user's --controllers or "valid:" list shows them (docs/testing.md).
FWS := $(WS)/fixtures
JOBS ?= 2
# Debian's ROS needs the system python, not a pyenv one that may come first on PATH.
export PATH := /usr/bin:/bin:$(PATH)
export PYENV_VERSION := system
export ROS_HOME := $(WS)/ros_home
export ROS_LOG_DIR := $(WS)/ros_home/log
ENV := source $(WS)/devel/setup.bash
# The same arguments on every catkin_make: others would make catkin_make run cmake again each time.
CMAKE_ARGS := -DPYTHON_EXECUTABLE=/usr/bin/python3 -DCMAKE_BUILD_TYPE=Release -DCATKIN_ENABLE_TESTING=ON

DEBS := ros-core-dev libtf2-ros-dev librosbag-dev libbz2-dev libroslz4-dev libdivsufsort-dev libnodeletlib-dev libeigen3-dev libyaml-cpp-dev \
  libgtest-dev libbenchmark-dev python3-rospy python3-rosbag python3-rostest librostest-dev rosbash \
  ros-message-generation pluginlib-dev libnodeletlib-tools libvisualization-msgs-dev python3-matplotlib python3-numpy parallel catkin \
  python3-rosnode python3-rostopic python3-rosservice libboost-dev slurmctld slurmd slurm-client munge rviz python3-tf2-ros xvfb imagemagick \
  libdynamic-reconfigure-config-init-mutex-dev python3-dynamic-reconfigure libdiagnostic-updater-dev \
  python3-diagnostic-msgs openssh-server pybind11-dev
SUDO := $(shell [ "$$(id -u)" = 0 ] || echo sudo)

DEMO_ARGS ?= n_robots:=64 arena:=32x16 ticks:=6000 seed:=1

.PHONY: all deps build install fixtures demo test test-unit test-graph bench format clean paper-quick paper paper-96 ablation claim-variants
all: build

deps:
	missing=$$(for p in $(DEBS); do dpkg-query -W -f='$${Status}\n' $$p 2>/dev/null | grep -q 'install ok installed' || echo $$p; done)
	if [ -n "$$missing" ]; then
	  echo "Installing: $$missing"
	  $(SUDO) env DEBIAN_FRONTEND=noninteractive apt-get update -q
	  $(SUDO) env DEBIAN_FRONTEND=noninteractive apt-get install -y -q $$missing
	fi

build: deps
	mkdir -p $(WS)/src $(ROS_LOG_DIR) $(ROOT)/results
	# The package is linked entry by entry: one link back to the root would contain .ws itself, and
	# rosrun's `find -L` would go round it ("File system loop detected").
	[ ! -L $(WS)/src/swarm_forage ] || rm $(WS)/src/swarm_forage
	mkdir -p $(WS)/src/swarm_forage
	for f in $(ROOT)/*; do [ $$f = $(ROOT)/examples ] || ln -sfn $$f $(WS)/src/swarm_forage/; done
	find $(WS)/src/swarm_forage -maxdepth 1 -xtype l -delete
	rm -f $(WS)/src/swarm_forage/examples
	# The examples are packages of their own, built into the same workspace against swarm_forage.
	for p in $(ROOT)/examples/*/; do ln -sfn $${p%/} $(WS)/src/; done
	cd $(WS)
	catkin_make -j$(JOBS) $(CMAKE_ARGS) > >(grep -vE '^\[ *[0-9]+%\]|^Scanning|^Consolidate' || true)

# The install space, .ws/install (docs/testing.md, The install space). Configured afresh without a sourced
# devel space on CMAKE_PREFIX_PATH: catkin makes whatever is there the install space's underlays.
install: build
	cd $(WS)
	CMAKE_PREFIX_PATH= catkin_make --force-cmake install -j$(JOBS) $(CMAKE_ARGS) > >(grep -vE '^\[ *[0-9]+%\]|^Scanning|^Consolidate|^-- (Up-to-date|Installing)' || true)

fixtures: build
	$(ENV)
	mkdir -p $(FWS)/src
	for p in $(ROOT)/test/fixtures/*/; do ln -sfn $${p%/} $(FWS)/src/; done
	find $(FWS)/src -maxdepth 1 -xtype l -delete
	cd $(FWS)
	catkin_make -j$(JOBS) $(CMAKE_ARGS) > >(grep -vE '^\[ *[0-9]+%\]|^Scanning|^Consolidate' || true)

demo: build
	$(ENV)
	mkdir -p $(ROOT)/results
	rm -f $(ROOT)/results/demo.bag $(ROOT)/results/demo_incomplete.bag
	# roslaunch exits 0 even when a node died: forage checks how the run ended and fails with the reason.
	python3 $(ROOT)/scripts/forage record:=true bag:=$(ROOT)/results/demo.bag \
	  metrics_csv:=$(ROOT)/results/demo_metrics.csv $(DEMO_ARGS)
	python3 $(ROOT)/scripts/summarize_run.py $(ROOT)/results/demo.bag --csv $(ROOT)/results/demo_metrics.csv \
	  --plot $(ROOT)/results/demo.png

# The tests in tiers (docs/testing.md). test-unit: the gtests and test/python (plain unittest), no master, a few
# minutes; test-graph: the rostests (test/graph, test/sweep, the examples' and the fixtures'); test: both. Each
# prints `N passed, M failed` last (test/tools/count_test_results.py counts the JUnit results, since
# `catkin_make run_tests` exits 0 when tests fail) and exits non-zero on any failure or missing result.
UNIT_TARGETS := run_tests_swarm_forage_gtest run_tests_swarm_forage_python run_tests_swarm_forage_examples_gtest
GRAPH_TARGETS := run_tests_swarm_forage_rostest run_tests_swarm_forage_examples_rostest
UNIT_TESTS = $(wildcard $(ROOT)/test/python/test_*.py)
GRAPH_TESTS = $(wildcard $(ROOT)/test/graph/*.test $(ROOT)/test/sweep/*.test $(ROOT)/examples/*/test/*.test \
  $(ROOT)/test/fixtures/*/test/*.test)

# $(call run_tier,LOG,TARGETS,FIXTURES,TESTS): runs TARGETS in .ws (and the fixtures' rostests when FIXTURES is
# yes), then the gate: every test of TESTS has results, and the count.
define run_tier
	$(ENV)
	cd $(WS)
	rm -rf build/test_results $(FWS)/build/test_results
	# run_tests exits 0 on failing tests (non-zero only when a test fails to build): the results gate.
	status=0
	catkin_make -j$(JOBS) $(2) $(CMAKE_ARGS) > $(WS)/$(1) 2>&1 || status=$$?
	if [ "$(3)" = yes ]; then
	  # The fixtures' tests, in their workspace's environment; their results join this workspace's.
	  (source $(FWS)/devel/setup.bash && cd $(FWS) && catkin_make -j$(JOBS) run_tests $(CMAKE_ARGS)) \
	    >> $(WS)/$(1) 2>&1 || status=$$?
	fi
	mkdir -p build/test_results
	[ ! -d $(FWS)/build/test_results ] || cp -r $(FWS)/build/test_results/. build/test_results/
	grep -E '^\[ +(RUN|OK|FAILED|PASSED) +\]|^\[(swarm_forage|Testcase)|RESULT:|^ \* (TESTS|ERRORS|FAILURES)|^test_.* \.\.\. |^SKIPPED ' $(WS)/$(1) || true
	[ $$status = 0 ] || echo "catkin_make $(2) failed (exit $$status); see $(WS)/$(1)"
	for t in $(4); do
	  case $$t in
	    $(ROOT)/test/python/*) pkg=swarm_forage; f=python-$$(basename $$t .py).xml ;;
	    $(ROOT)/test/*/*/test/*|$(ROOT)/examples/*) pkg=$$(basename $$(dirname $$(dirname $$t))); f=rostest-test_$$(basename $$t .test).xml ;;
	    *) pkg=swarm_forage; rel=$${t#$(ROOT)/}; f=rostest-$${rel//\//_}; f=$${f%.test}.xml ;;
	  esac
	  [ -f build/test_results/$$pkg/$$f ] || { echo "no results from $$pkg/$${t#$(ROOT)/}"; status=1; }
	done
	catkin_test_results build/test_results > /dev/null || status=1
	python3 $(ROOT)/test/tools/count_test_results.py build/test_results || status=1
	exit $$status
endef

test-unit: build
	$(call run_tier,test_unit.log,$(UNIT_TARGETS),no,$(UNIT_TESTS))

test-graph: fixtures
	$(call run_tier,test_graph.log,$(GRAPH_TARGETS),yes,$(GRAPH_TESTS))

test: fixtures
	$(call run_tier,run_tests.log,run_tests,yes,$(UNIT_TESTS) $(GRAPH_TESTS))

# The paper's study, reduced or in full (docs/study.md); both resume where they stopped.
# `paper --quick --dry-run` (make paper-quick DRY_RUN=1) estimates it for this machine as it is now.
# MODEL=swarm_forage (and QUIRKS=a,b) runs the study under the corrected model (docs/FIDELITY.md) into
# results/paper_quick_swarm_forage; the default model's (fordyca_2019) results are in results/paper_quick.
MODEL ?= fordyca_2019
QUIRKS ?=
# QUICK_ARGS: 3 seeds per group to start (the fewest a verdict is decided on), then rounds of more seeds, up to 10,
# for the groups of claims still undecided.
QUICK_ARGS ?= --decide --cap 10
paper-quick: build
	$(ENV)
	python3 $(ROOT)/scripts/paper --quick $(QUICK_ARGS) --model $(MODEL) $(if $(QUIRKS),--quirks $(QUIRKS)) \
	  $(if $(DRY_RUN),--dry-run) $(if $(PUBLISH),--publish $(PUBLISH))

# The 96x48 arm, claims (c) and (d): CRW and DPO at N = 2,048 ... 16,384 and GP-DPO at 16,384, 10 seeds each
# (docs/paper_96 holds the result and the time it took); MODEL= as for paper-quick.
# PUBLISH=DIR (paper-quick and paper-96): then copy the report, figures and every sweep's tables into DIR, as
# docs/paper_quick and docs/paper_96 are committed (`make paper-96 PUBLISH=docs/paper_96`); `recommend` reads them.
paper-96: build
	$(ENV)
	python3 $(ROOT)/scripts/paper --arm-96 --model $(MODEL) $(if $(QUIRKS),--quirks $(QUIRKS)) \
	  $(if $(DRY_RUN),--dry-run) $(if $(PUBLISH),--publish $(PUBLISH))

# The ablation of FORDYCA 2019's quirks (docs/FIDELITY.md): config/experiments/ablation_*.yaml through sweep,
# the model an axis of each, into results/ablation, then results/ablation/table.md and runs.csv. Resumes where it
# stopped; DRY_RUN=1 estimates it; PUBLISH=docs/ablation copies the table there; ABLATION_ARGS: more paper words
# (-j 1, --reuse results/paper_96/ideal_96x48, --report-only).
ABLATION_ARGS ?=
ablation: build
	$(ENV)
	python3 $(ROOT)/scripts/paper --ablation $(ABLATION_ARGS) $(if $(DRY_RUN),--dry-run) \
	  $(if $(PUBLISH),--publish $(PUBLISH))

# Where each claim turns (docs/decisions.md): each model's studies' claims under the authors' metric definitions,
# arena by arena, beside the thresholds (scripts/claim_variants): FORDYCA's model into docs/claim_variants.md,
# the corrected one into docs/claim_variants_swarm_forage.md, each from the records there are.
VARIANT_STUDIES ?= $(wildcard $(ROOT)/results/paper_quick $(ROOT)/results/paper_96)
VARIANT_CORRECTED ?= $(wildcard $(ROOT)/results/paper_quick_swarm_forage $(ROOT)/results/paper_96_swarm_forage)
claim-variants: build
	$(ENV)
	cd $(ROOT)
	if [ -z "$(VARIANT_STUDIES)$(VARIANT_CORRECTED)" ]; then echo "claim-variants: no study in results/ (make paper-quick, paper-96)" >&2; exit 2; fi
	$(if $(VARIANT_STUDIES),python3 scripts/claim_variants $(patsubst $(ROOT)/%,%,$(VARIANT_STUDIES)) --output docs/claim_variants.md)
	$(if $(VARIANT_CORRECTED),python3 scripts/claim_variants $(patsubst $(ROOT)/%,%,$(VARIANT_CORRECTED)) --output docs/claim_variants_swarm_forage.md)

# DRY_RUN=1 (make paper DRY_RUN=1, also paper-quick, paper-96 and ablation): every sweep's plan and estimate, summed
# (runs, reuses, forks, robot-ticks, hours, disk); nothing runs.
paper: build
	$(ENV)
	python3 $(ROOT)/scripts/paper $(PAPER_ARGS) $(if $(DRY_RUN),--dry-run)

# Every throughput figure of docs/design.md, Performance targets: table, results/bench/bench.csv and .png.
bench: build
	$(ENV)
	python3 $(ROOT)/bench/bench_all.py $(BENCH_ARGS)

format:
	clang-format -i $$(git ls-files '*.cpp' '*.hpp')

clean:
	rm -rf $(WS)
