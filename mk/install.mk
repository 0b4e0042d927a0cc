# SPDX-License-Identifier: BSD-3-Clause
# Installing wsgsim:
#   make programs                 every program and its man page
#   make install [PREFIX=/usr/local] [DESTDIR=]   programs, man pages, units,
#                                 example configuration, DBC and docs, and
#                                 $(SYSCONFDIR)/wsgsim for the units' files (not the
#                                 Python package: its .deb, or PYTHONPATH=python;
#                                 install says so)
#   make uninstall                removes exactly what install put there
#   make docs-plot                regenerates docs/wsgplot-demo.png
# The man pages are generated from each program's --help and --version by
# help2man (man/*.h2m add the sections --help has no room for), so a new
# option is in the page as soon as it is in --help. The pages name the
# installed paths: @DOCDIR@, @PRIVATE_DIR@ and @SYSCONFDIR@ in man/*.h2m
# become this install's, and @GZ@ becomes DOC_SUFFIX (.gz for the Debian
# package, whose dh_compress compresses the documents).
PREFIX ?= /usr/local
BINDIR ?= $(PREFIX)/bin
DATADIR ?= $(PREFIX)/share
MANDIR ?= $(DATADIR)/man
DOCDIR ?= $(DATADIR)/doc/wsgsim
SYSCONFDIR ?= /etc
SYSTEMDUNITDIR ?= $(PREFIX)/lib/systemd/system
DOC_SUFFIX ?=
INSTALL ?= install

# Each program once; the C ones are built, the Python ones are scripts.
# The binary protocol client needs its module beside it: both go to
# $(PRIVATE_DIR), and $(BINDIR)/wsgbin is a relative link to it.
C_PROGRAMS := $(BUILD)/wsgsim $(BUILD)/fingersim $(BUILD)/wsgproxy
SCRIPT_PROGRAMS := tools/wsgctl tools/wsgplot
# The probe reads the binary protocol with the client's module: beside it too.
PROBE := tools/wsgprobe
BIN_CLIENT := tools/wsgbin
BIN_CLIENT_MODULE := tools/wsgbinproto.py
# The calibration tools share their module the same way.
TWIN_PROGRAMS := tools/wsgcalib tools/wsgfit tools/wsgcheck
TWIN_MODULE := tools/wsgtwin.py
PRIVATE_DIR = $(DATADIR)/wsgsim
PROGRAMS := $(C_PROGRAMS) $(SCRIPT_PROGRAMS) $(BIN_CLIENT) $(PROBE) $(TWIN_PROGRAMS)
PROGRAM_NAMES := $(notdir $(PROGRAMS))
MAN_PAGES := $(patsubst %,$(BUILD)/man/%.1,$(PROGRAM_NAMES))
UNITS := wsgsim.service wsgsim@.service
DOCS := README.md $(wildcard docs/*.md docs/*.png)
MAN_DEBS := help2man

# The programs name the installed example configuration (wsgsim's --help,
# and so its man page, and a configuration file's unknown key): rebuilt
# when the paths change. The name is host/config's (config_file.h), so every
# object of host/config/ is, whichever of its files prints it.
HOST_CFLAGS += -DWSGSIM_EXAMPLE_CONFIG='"$(DOCDIR)/examples/wsgsim.example.ini"'
# The shipped timing profiles (docs/timing.md): a run from the build tree
# finds profiles/timing beside build/, an installed one this folder.
TIMING_PROFILES := $(sort $(wildcard profiles/timing/*.ini))
TIMING_DIR = $(PRIVATE_DIR)/timing
HOST_CFLAGS += -DWSGSIM_TIMING_DIR='"$(TIMING_DIR)"'
# The physics scene's gripper model and default scene (docs/physics.md).
HOST_CFLAGS += -DWSGSIM_PHYSICS_DIR='"$(PRIVATE_DIR)/physics"'
$(filter $(BUILD)/obj/host/config/%,$(HOST_OBJ)): $(BUILD)/man/paths

.PHONY: programs man install uninstall docs-plot
## build every program and its man page
programs: $(PROGRAMS) man

## build the man pages (help2man)
man: $(MAN_PAGES)

# help2man runs the program: the page says what this build does.
# SOURCE_DATE_EPOCH (set by dpkg-buildpackage) fixes the date in the page.
MAN_PATHS := $(BUILD)/man/paths
MAN_PATH_VALUES := $(DOCDIR) $(PRIVATE_DIR) $(SYSCONFDIR) $(DOC_SUFFIX)
MAN_SED := -e 's|@DOCDIR@|$(DOCDIR)|g' -e 's|@PRIVATE_DIR@|$(PRIVATE_DIR)|g' \
	-e 's|@SYSCONFDIR@|$(SYSCONFDIR)|g' -e 's|@GZ@|$(DOC_SUFFIX)|g'

.PHONY: man-paths
# The paths the pages name, rewritten only when they change (another PREFIX).
$(MAN_PATHS): man-paths
	@mkdir -p $(dir $@)
	@echo '$(MAN_PATH_VALUES)' | cmp -s - $@ || echo '$(MAN_PATH_VALUES)' > $@

$(BUILD)/man/%.1: man/%.h2m $(MAN_PATHS) | man-deps
	@mkdir -p $(dir $@)
	sed $(MAN_SED) $< > $@.h2m
	help2man --no-info --include=$@.h2m --output=$@.tmp \
		$(filter %/$*,$(PROGRAMS)) && mv $@.tmp $@ && rm $@.h2m

$(BUILD)/man/wsgsim.1: $(BUILD)/wsgsim
$(BUILD)/man/fingersim.1: $(BUILD)/fingersim
$(BUILD)/man/wsgctl.1: tools/wsgctl
$(BUILD)/man/wsgplot.1: tools/wsgplot
$(BUILD)/man/wsgbin.1: tools/wsgbin $(BIN_CLIENT_MODULE)
$(BUILD)/man/wsgprobe.1: $(PROBE) $(BIN_CLIENT_MODULE)
$(BUILD)/man/wsgproxy.1: $(BUILD)/wsgproxy
$(BUILD)/man/wsgcalib.1: tools/wsgcalib $(TWIN_MODULE)
$(BUILD)/man/wsgfit.1: tools/wsgfit $(TWIN_MODULE)
$(BUILD)/man/wsgcheck.1: tools/wsgcheck $(TWIN_MODULE)

.PHONY: man-deps
## install help2man
man-deps:
	@mk/deps.sh $(MAN_DEBS)

# The units name the installed paths, so they are written at install time.
## install programs, man pages, units, docs (PREFIX=/usr/local DESTDIR=)
install: $(PROGRAMS) man
	$(INSTALL) -d $(DESTDIR)$(BINDIR) $(DESTDIR)$(MANDIR)/man1 $(DESTDIR)$(SYSTEMDUNITDIR) \
		$(DESTDIR)$(DOCDIR)/examples $(DESTDIR)$(PRIVATE_DIR) $(DESTDIR)$(SYSCONFDIR)/wsgsim \
		$(DESTDIR)$(TIMING_DIR)
	$(INSTALL) -m 755 $(C_PROGRAMS) $(SCRIPT_PROGRAMS) $(DESTDIR)$(BINDIR)/
	$(INSTALL) -m 755 $(PROBE) $(DESTDIR)$(PRIVATE_DIR)/
	ln -sf $$(realpath -m --relative-to=$(BINDIR) $(PRIVATE_DIR)/$(notdir $(PROBE))) \
		$(DESTDIR)$(BINDIR)/$(notdir $(PROBE))
	$(INSTALL) -m 755 $(BIN_CLIENT) $(DESTDIR)$(PRIVATE_DIR)/
	$(INSTALL) -m 644 $(BIN_CLIENT_MODULE) $(DESTDIR)$(PRIVATE_DIR)/
	ln -sf $$(realpath -m --relative-to=$(BINDIR) $(PRIVATE_DIR)/$(notdir $(BIN_CLIENT))) \
		$(DESTDIR)$(BINDIR)/$(notdir $(BIN_CLIENT))
	$(INSTALL) -m 755 $(TWIN_PROGRAMS) $(DESTDIR)$(PRIVATE_DIR)/
	$(INSTALL) -m 644 $(TWIN_MODULE) $(DESTDIR)$(PRIVATE_DIR)/
	for program in $(notdir $(TWIN_PROGRAMS)); do \
		ln -sf $$(realpath -m --relative-to=$(BINDIR) $(PRIVATE_DIR)/$$program) \
			$(DESTDIR)$(BINDIR)/$$program || exit 1; \
	done
	$(INSTALL) -m 644 $(MAN_PAGES) $(DESTDIR)$(MANDIR)/man1/
	for unit in $(UNITS); do \
		sed -e 's|@BINDIR@|$(BINDIR)|g' -e 's|@SYSCONFDIR@|$(SYSCONFDIR)|g' \
			-e 's|@DOCDIR@|$(DOCDIR)|g' dist/systemd/$$unit.in \
			> $(DESTDIR)$(SYSTEMDUNITDIR)/$$unit && chmod 644 $(DESTDIR)$(SYSTEMDUNITDIR)/$$unit \
			|| exit 1; \
	done
	$(INSTALL) -m 644 $(DOCS) $(DESTDIR)$(DOCDIR)/
	$(INSTALL) -m 644 docs/wsgsim.example.ini $(DESTDIR)$(DOCDIR)/examples/
	$(INSTALL) -m 644 docs/finger-bus.dbc $(DESTDIR)$(PRIVATE_DIR)/
	$(INSTALL) -m 644 $(TIMING_PROFILES) $(DESTDIR)$(TIMING_DIR)/
	$(INSTALL) -d $(DESTDIR)$(PRIVATE_DIR)/physics
	$(INSTALL) -m 644 physics/*.xml $(DESTDIR)$(PRIVATE_DIR)/physics/
	@echo "install: the Python package (python/: the wsgsim module and its pytest plugin)"
	@echo "install: is not installed by make install. Use the python3-wsgsim package"
	@echo "install: (make deb; apt install ./build/deb/python3-wsgsim_*.deb), or from this"
	@echo "install: tree PYTHONPATH=$(abspath python) and pytest -p wsgsim.pytest_plugin"

## remove exactly what install put there
uninstall:
	rm -f $(addprefix $(DESTDIR)$(BINDIR)/,$(PROGRAM_NAMES)) \
		$(patsubst %,$(DESTDIR)$(MANDIR)/man1/%.1,$(PROGRAM_NAMES)) \
		$(addprefix $(DESTDIR)$(SYSTEMDUNITDIR)/,$(UNITS)) \
		$(addprefix $(DESTDIR)$(PRIVATE_DIR)/,finger-bus.dbc $(notdir $(BIN_CLIENT) \
			$(BIN_CLIENT_MODULE) $(PROBE) $(TWIN_PROGRAMS) $(TWIN_MODULE)))
	rm -rf $(DESTDIR)$(DOCDIR) $(DESTDIR)$(PRIVATE_DIR)/__pycache__ $(DESTDIR)$(PRIVATE_DIR)/physics $(DESTDIR)$(TIMING_DIR)
	-rmdir $(DESTDIR)$(PRIVATE_DIR) $(DESTDIR)$(SYSCONFDIR)/wsgsim 2>/dev/null

# A deterministic run on the paused clock, drawn by tools/wsgplot.
## regenerate docs/wsgplot-demo.png
docs-plot: $(BUILD)/wsgsim
	@mk/deps.sh gnuplot-nox
	python3 tests/pkg/demo_record.py $(BUILD)/wsgsim $(BUILD)/demo-record.txt
	tools/wsgplot $(BUILD)/demo-record.txt -o docs/wsgplot-demo.png \
		--title "wsgsim: HOME, GRIP a 40 mm part, RELEASE (paused clock, 20 ms steps)"
