/* SPDX-License-Identifier: BSD-3-Clause */
/* The last lines of each open connection, for the page's connection list:
 * a ring of WEB_LINES_KEPT per connection, GCL text as sent ("> POS?",
 * "< POS=12.000"), binary frames by command name. Kept only while the web
 * server is on, and only from the first time a client asks for a state or
 * opens an event stream (web_lines_watch): until someone looks, a line costs
 * one test. Storage is a table allocated when the server starts, indexed by
 * a hash of (device, connection id); two connections that meet in one slot
 * share it, the newer one's lines winning (docs/web.md). */
#ifndef HOST_WEB_LINES_H
#define HOST_WEB_LINES_H

#include <stdbool.h>
#include <stddef.h>

#include "web/web_json.h"
#include "wsg/wsg_conn.h"

#define WEB_LINES_KEPT 8

void web_lines_enable(void);
void web_lines_disable(void);
/* True while the server is on: the observer hub then watches messages. */
bool web_lines_enabled(void);
/* A client looks: lines are kept from now on. */
void web_lines_watch(void);
/* True once a client looks: read inline by the observers, so that a line
 * nobody watches costs one test and no call. Set by web_lines_watch(). */
extern bool web_lines_watched;
void web_lines_record(const wsg_conn_t *c, bool incoming, const char *bytes, size_t len);
/* A message from the client (incoming, shown as "> ...") or to it ("< ..."). */
static inline void web_lines_note(const wsg_conn_t *c, bool incoming, const char *bytes, size_t len)
{
    if (web_lines_watched) {
        web_lines_record(c, incoming, bytes, len);
    }
}
/* The connection's last lines, oldest first, as an array (empty when none). */
void web_lines_write(web_json_t *j, const char *key, const wsg_conn_t *c);
/* "gcl", "binary" or "undetected" (no byte yet on an auto-detecting port). */
const char *web_lines_protocol(const wsg_conn_t *c);
/* The observer for devices without the hub's (devices 1.. of a fleet). */
const wsg_conn_observer_t *web_lines_observer(void);

#endif
