# SPDX-License-Identifier: BSD-3-Clause
# Static checks of the sources, part of `make check`:
#   lint   cppcheck over every C source (firmware/, hal/, host/, tools/,
#          tests/), clean but for the findings mk/lint.supp explains; and
#          every target of the build described for `make help`
#   help   every target of the build, with its one line ('## ' above its
#          rule: mk/help.py)
LINT_DEBS := cppcheck
LINT_DIRS := firmware hal host tools tests
CPPCHECK_JOBS ?= 2
CPPCHECK := cppcheck -q --std=c11 --enable=warning,portability,performance \
	--error-exitcode=1 --suppressions-list=mk/lint.supp -j$(CPPCHECK_JOBS) \
	-D_GNU_SOURCE $(CORE_INC) $(HOST_INC) -Itests -Itests/fake
HELP_SOURCES := Makefile $(sort $(wildcard mk/*.mk))

.PHONY: lint help
# Not in the SAN=1 pass, which runs the suites of C code (docs/testing.md):
# the sources are the same whatever SAN says.
ifneq ($(SAN),1)
CHECK_TARGETS += lint
endif

## cppcheck over every C source, and every target described for make help
lint:
	@mk/deps.sh $(LINT_DEBS)
	$(CPPCHECK) $(LINT_DIRS)
	@python3 mk/help.py --check $(HELP_SOURCES)

## list every target with its one line
help:
	@python3 mk/help.py $(HELP_SOURCES)
