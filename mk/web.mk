# SPDX-License-Identifier: BSD-3-Clause
# The web interface (docs/web.md): the page's files built into
# build/wsgsim, and its end-to-end tests.
#   web-tests   tests/web/: the peer and slow-client rules' Check tests, then the end-to-end
#               tests against build/wsgsim (every route and error)
# The page is webui/* (index.html, app.js, style.css), built in; the chart
# library is Debian's libjs-dygraphs, which wsgsim reads at run time from
# /usr/share/javascript/dygraphs (host/web/web_static.c): never built in,
# never fetched from the internet.
WEB_PAGE_FILES := $(sort $(wildcard webui/*))
WEB_ASSETS_C := $(BUILD)/gen/web_assets.c

.PHONY: web-tests
CHECK_TARGETS += web-tests

WEB_ASSETS_LIST := $(BUILD)/gen/web_assets.list

.PHONY: web-assets-list
# The names of webui/'s files, rewritten only when they change: a file removed
# from webui/ rebuilds the table as a file added or edited does.
$(WEB_ASSETS_LIST): web-assets-list
	@mkdir -p $(dir $@)
	@echo '$(WEB_PAGE_FILES)' | cmp -s - $@ || echo '$(WEB_PAGE_FILES)' > $@

$(WEB_ASSETS_C): mk/web_assets.py $(WEB_PAGE_FILES) $(WEB_ASSETS_LIST) | deps
	@mkdir -p $(dir $@)
	$(call quiet,GEN,$@)python3 mk/web_assets.py $@ $(WEB_PAGE_FILES)

$(BUILD)/obj/gen/web_assets.o: $(WEB_ASSETS_C) host/web/web_assets.h
	@mkdir -p $(dir $@)
	$(call quiet,CC,$<)$(CC) $(CFLAGS_BASE) $(LTO) -Ihost -c $< -o $@

# Check tests of single modules: tests/web/test_NAME.c against host/web/web_NAME.c.
WEB_UNIT_TESTS := $(addprefix $(BUILD)/tests/web_,$(addsuffix _test,peer intake event_cache))

$(BUILD)/tests/web_%_test: tests/web/test_%.c $(BUILD)/obj/host/web/web_%.o $(CORE_LIBS)
	@mkdir -p $(dir $@)
	$(CC) $(HOST_CFLAGS) $(shell pkg-config --cflags check) $(LDFLAGS_BASE) -o $@ $^ \
		$(shell pkg-config --libs check libcjson)

## the web server's Check tests and its end-to-end tests (every route)
web-tests: $(BUILD)/wsgsim $(WEB_UNIT_TESTS)
	for t in $(WEB_UNIT_TESTS); do $(CHECK_ENV) $$t || exit 1; done
	WSGSIM=$(abspath $(BUILD)/wsgsim) python3 tests/run_suite.py --jobs $(SUITE_JOBS) web tests/web
