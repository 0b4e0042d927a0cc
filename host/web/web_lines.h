/* SPDX-License-Identifier: BSD-3-Clause */
/* The last lines of each open connection, for the page's connection list:
 * a ring of WEB_LINES_KEPT per connection, GCL text as sent ("> POS?",
 * "< POS=12.000"), binary frames by command name. Kept only while the web
 * server is on, and only from the first time a client asks for a state or
 * opens an event stream (web_lines_watch): until someone looks, the devices
 * are not observed and a line costs nothing. Storage is a table allocated when the server starts,
 * indexed by a hash of (device, connection id); two connections that meet in one slot share it, the
 * newer one's lines winning (docs/web.md). */
#ifndef HOST_WEB_LINES_H
#define HOST_WEB_LINES_H

#include <stdbool.h>
#include <stddef.h>

#include "web/web_json.h"
#include "wsg/wsg_conn.h"

#define WEB_LINES_KEPT 8

typedef struct web_lines web_lines_t;

/* The table, for a fleet of `devices`; NULL when out of memory. */
web_lines_t *web_lines_create(unsigned devices);
/* Keeps device `index`'s lines (below the create's count) from the first
 * look on (web_lines_watch). */
void web_lines_attach(web_lines_t *wl, wsg_device_t *dev, unsigned index);
/* While the devices it was attached to live on: it leaves them (the web
 * server stops before the fleet). Nothing for NULL. */
void web_lines_destroy(web_lines_t *wl);
/* A client looks: lines are kept from now on, on every attached device
 * (O(devices), once). Nothing for NULL. */
void web_lines_watch(web_lines_t *wl);
/* The connection's last lines, oldest first, as an array (empty when none,
 * or wl NULL). */
void web_lines_write(web_lines_t *wl, web_json_t *j, const char *key, const wsg_conn_t *c);
/* "gcl", "binary" or "undetected" (no byte yet on an auto-detecting port). */
const char *web_lines_protocol(web_lines_t *wl, const wsg_conn_t *c);

#endif
