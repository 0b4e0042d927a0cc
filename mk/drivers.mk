# SPDX-License-Identifier: BSD-3-Clause
# The public drivers against wsgsim; not part of `make check` (their rates
# are wall-clock figures, docs/testing-your-driver.md "Real drivers against
# wsgsim"):
#   make drivers                   install Debian's ROS 1 packages (DRIVERS_DEBS,
#                                  not build dependencies of wsgsim), fetch
#                                  the drivers into DRIVERS_DIR and build them
#   make drivers-run DRIVER=MODE [DRIVER_SECONDS=10] [DRIVER_WSGSIM_ARGS='--timing wsg50']
#                                  one driver mode (DRIVER=all: each) against
#                                  build/wsgsim in a private network
#                                  namespace; its rates as JSON
#   make drivers-bench             every mode under each of DRIVERS_BENCH_SETS
#                                  (wsgsim option sets), one table line each
# The sources: a git URL (default), a checkout, a bare git directory or a
# plain folder each.
DRIVERS_DIR ?= $(or $(XDG_CACHE_HOME),$(HOME)/.cache)/wsgsim-drivers
DRIVERS_WSG50_ROS ?= https://github.com/nalt/wsg50-ros-pkg
DRIVERS_UMI ?= https://github.com/real-stanford/universal_manipulation_interface
DRIVERS_DRAKE_SCHUNK ?= https://github.com/RobotLocomotion/drake-schunk-driver
DRIVER ?= all
DRIVER_SECONDS ?= 10
DRIVER_WSGSIM_ARGS ?=
# the device's pace and the wire: the rows of docs/benchmark.md, "Public
# drivers against wsgsim"; sets separated by commas
DRIVERS_BENCH_SETS ?= --timing ideal,--timing wsg50,--timing ideal --net rough,--timing wsg50 --net rough
# Debian bookworm's ROS 1 (Noetic-era) packages that build and run
# wsg50-ros-pkg's node: catkin and message generation, roscpp and the
# messages it includes, the master, and rospy for the rate counter; util-linux
# for unshare; clang for the build.
DRIVERS_DEBS := catkin clang git libroscpp-dev libsensor-msgs-dev libstd-msgs-dev \
	libstd-srvs-dev python3-genmsg python3-gencpp python3-rosmaster python3-rospy \
	ros-message-generation ros-message-runtime ros-sensor-msgs ros-std-msgs \
	ros-std-srvs util-linux

.PHONY: drivers drivers-deps drivers-run drivers-bench

## install the ROS 1 packages the public drivers need (DRIVERS_DEBS)
drivers-deps:
	@mk/deps.sh $(DRIVERS_DEBS)

## fetch and build wsg50-ros-pkg, UMI's and Drake's drivers into DRIVERS_DIR
drivers: drivers-deps
	tools/drivers/build.sh $(DRIVERS_DIR) $(DRIVERS_WSG50_ROS) $(DRIVERS_UMI) \
		$(DRIVERS_DRAKE_SCHUNK)

## run a public driver's mode against build/wsgsim (DRIVER=MODE|all, JSON)
drivers-run: $(BUILD)/wsgsim
	tools/drivers/run_driver.py $(DRIVER) --seconds $(DRIVER_SECONDS) \
		--drivers $(DRIVERS_DIR) --wsgsim $(BUILD)/wsgsim -- $(DRIVER_WSGSIM_ARGS)

# A driver that breaks under a set is a result (its line says how), not a
# failure of the target.
## every driver mode under each wsgsim option set (DRIVERS_BENCH_SETS), as a table
drivers-bench: $(BUILD)/wsgsim
	@sets='$(DRIVERS_BENCH_SETS)'; IFS=,; for set in $$sets; do \
		echo "== wsgsim $$set"; \
		IFS=' '; tools/drivers/run_driver.py all --table --seconds $(DRIVER_SECONDS) \
			--drivers $(DRIVERS_DIR) --wsgsim $(BUILD)/wsgsim -- $$set || true; \
	done
