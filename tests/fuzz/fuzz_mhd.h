/* SPDX-License-Identifier: BSD-3-Clause */
/* What the web routes' fuzz targets share (fuzz_web.c, fuzz_store.c): a
 * stand-in for the part of libmicrohttpd the routes call (the server's
 * socket side, web_server.c, is not linked) and one request at a time
 * through the routes, its reply checked.
 *
 * A request's bytes: the first picks the method (bits 0-2), whether the
 * peer may use the simulation routes (bit 3) and the simulated time to run
 * afterwards (bits 4-7); then the URL up to the first '\n' (a query after
 * '?' gives the GET arguments), then the body (NUL bytes included, at most
 * WEB_BODY_MAX bytes). */
#ifndef FUZZ_MHD_H
#define FUZZ_MHD_H

#include <stddef.h>
#include <stdint.h>

#include "options.h"
#include "web/web_internal.h"

/* The host started with opts (fuzz_host_start) and app set up for its
 * devices as the web server sets itself up. */
void fuzz_mhd_app_start(web_app_t *app, const host_options_t *opts);
/* app released as the server stops, then the host stopped. */
void fuzz_mhd_app_stop(web_app_t *app);
/* One request (n bytes at p, the layout above; url_prefix goes before its
 * URL) through app's routes; aborts when the reply breaks a rule. */
void fuzz_mhd_request(web_app_t *app, const uint8_t *p, size_t n, const char *url_prefix);
/* A text no reply may hold from now on (NULL: none). */
void fuzz_mhd_forbid(const char *text);

#endif
