# SPDX-License-Identifier: BSD-3-Clause
# The Debian packages (debian/): wsgsim and python3-wsgsim.
#   make deb    build/deb/wsgsim_VERSION_ARCH.deb and python3-wsgsim_VERSION_all.deb
# dpkg-buildpackage runs on a copy of the tree in build/deb/ (its clean step
# would otherwise wipe this tree's build/), and only when a source file
# changed since the last package build. It runs with the system's PATH: a
# package is built with Debian's toolchain and Python, not a user's; and in
# an empty environment but DEB_BUILD_OPTIONS, without the calling make's
# variables (SAN=1 ...): the package is built as Debian builds it. It takes
# minutes: mk/progress.py shows its stages (dpkg-buildpackage's and dh's
# steps) as they come, and the whole output is in build/deb/build.log.
DEB_PATH := /usr/sbin:/usr/bin:/sbin:/bin
DEB_DIR := build/deb
DEB_VERSION := $(shell dpkg-parsechangelog -l debian/changelog -S Version 2>/dev/null)
DEB_ARCH := $(shell dpkg --print-architecture 2>/dev/null)
DEB_SRC := $(DEB_DIR)/wsgsim-$(DEB_VERSION)
DEB_FILES := $(DEB_DIR)/wsgsim_$(DEB_VERSION)_$(DEB_ARCH).deb \
	$(DEB_DIR)/python3-wsgsim_$(DEB_VERSION)_all.deb
# Every file of the source tree but build/, .git and Python's caches.
DEB_STAGES := ^(dpkg-buildpackage: info: |dpkg-deb: building |   dh_|   debian/rules )
DEB_INPUTS := $(shell find . \( -path ./build -o -path ./.git -o -name __pycache__ \) -prune \
	-o -type f -print 2>/dev/null)

.PHONY: deb deb-deps
## build the Debian packages in build/deb/ (wsgsim, python3-wsgsim)
deb: $(DEB_FILES)

## install what a package build needs
deb-deps:
	@mk/deps.sh $(CHECK_DEBS)

$(DEB_FILES) &: $(DEB_INPUTS) | deb-deps
	@echo "deb: the tree copied to $(DEB_SRC), built there with dpkg-buildpackage"
	@rm -rf $(DEB_DIR) && mkdir -p $(DEB_SRC)
	@tar -cf - --exclude=./build --exclude=./.git --exclude=__pycache__ . | tar -xf - -C $(DEB_SRC)
	@cd $(DEB_SRC) && env -i PATH=$(DEB_PATH) HOME="$$HOME" \
		DEB_BUILD_OPTIONS="$$DEB_BUILD_OPTIONS" \
		/usr/bin/python3 $(abspath mk/progress.py) deb $(abspath $(DEB_DIR))/build.log \
		'$(DEB_STAGES)' -- dpkg-buildpackage -us -uc -b
	@ls $(DEB_FILES)
