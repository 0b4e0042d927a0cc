# SPDX-License-Identifier: BSD-3-Clause
# The web interface (issue 13, docs/web.md): the page's files built into
# build/wsgsim, and its end-to-end tests.
#   web-tests   tests/web/ against build/wsgsim (every route and error)
# The page is web/* (index.html, app.js, style.css); the chart library is
# Debian's libjs-dygraphs, embedded at build time, never fetched at run time.
WEB_PAGE_FILES := $(sort $(wildcard web/*))
WEB_DYGRAPH_DIR := /usr/share/javascript/dygraphs
WEB_DYGRAPH_FILES := $(WEB_DYGRAPH_DIR)/dygraph.min.js $(WEB_DYGRAPH_DIR)/dygraph.min.css
WEB_ASSETS_C := $(BUILD)/gen/web_assets.c

.PHONY: web-tests
CHECK_TARGETS += web-tests

# libjs-dygraphs is a build dependency (debian/control): `deps` installs it.
$(WEB_ASSETS_C): mk/web_assets.py $(WEB_PAGE_FILES) | deps
	@mkdir -p $(dir $@)
	python3 mk/web_assets.py $@ $(WEB_PAGE_FILES) $(WEB_DYGRAPH_FILES)

$(BUILD)/obj/gen/web_assets.o: $(WEB_ASSETS_C) host/web/web_assets.h
	@mkdir -p $(dir $@)
	$(CC) $(CFLAGS_BASE) -Ihost -c $< -o $@

web-tests: $(BUILD)/wsgsim
	WSGSIM=$(abspath $(BUILD)/wsgsim) python3 tests/web/run.py
