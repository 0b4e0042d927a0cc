# SPDX-License-Identifier: BSD-3-Clause
# The device page (webui/) in a browser: tests/browser with Debian's
# headless Chromium, chromium-driver and python3-selenium (<!nocheck> test
# dependencies in debian/control, installed by deps-check).
#   make browser-tests        the page against build/wsgsim's HTTP server;
#                             its screenshot goes to build/browser/
#   make browser-screenshot   the same, refreshing docs/img/live-view.png
BROWSER_PYTHON := /usr/bin/python3
BROWSER_TESTS = WSGSIM=$(abspath $(BUILD)/wsgsim) $(BROWSER_PYTHON) tests/browser/test_page.py

.PHONY: browser-tests browser-screenshot
# Not in the SAN=1 pass, which runs the suites of C code (docs/testing.md).
ifneq ($(SAN),1)
CHECK_TARGETS += browser-tests
endif

## the device page in headless Chromium against build/wsgsim
browser-tests: deps-check $(BUILD)/wsgsim
	SCREENSHOT=$(abspath $(BUILD)/browser/live-view.png) $(BROWSER_TESTS)

## the same, refreshing docs/img/live-view.png
browser-screenshot: deps-check $(BUILD)/wsgsim
	SCREENSHOT=$(abspath docs/img/live-view.png) $(BROWSER_TESTS)
