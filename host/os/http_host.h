/* SPDX-License-Identifier: BSD-3-Clause */
/* The names the web server answers to (docs/web.md, "Host names"): a page
 * that reaches the server under a name an attacker re-points at it (DNS
 * rebinding) sends that name in its Host header, and is refused. A rule on
 * text alone, below both the configuration that reads the allowed names
 * and the web server that applies them. */
#ifndef HOST_OS_HTTP_HOST_H
#define HOST_OS_HTTP_HOST_H

#include <stdbool.h>
#include <stddef.h>

/* True when a Host header value ("name", "name:port", "[v6]:port") names
 * this server: an IPv4 or bracketed IPv6 literal (rebinding needs a name),
 * localhost or a name under .localhost (never re-pointed, RFC 6761), or one
 * of the allowed names. allowed holds count comma-separated lists of names
 * (--http-allow-host); "*" allows every Host. Names compare without case and
 * without one trailing dot. */
bool http_host_allowed(const char *host, const char *const *allowed, size_t count);
/* True when text is a comma-separated list of host names (letters, digits,
 * '-' and '.', at most 253 characters each) or "*": what --http-allow-host
 * and [network] http_allow_host take. */
bool http_host_list_valid(const char *text);

#endif
