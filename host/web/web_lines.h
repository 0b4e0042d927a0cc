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

typedef struct web_lines_ring web_lines_ring_t;

/* The lines of one web server (embedded in its routes' state). */
typedef struct web_lines {
    web_lines_ring_t *rings; /* the table while the server is on, else NULL */
    /* True once a client looks: read inline by the observers, so that a line
     * nobody watches costs one test and no call. Set by web_lines_watch(). */
    bool watched;
} web_lines_t;

void web_lines_enable(web_lines_t *lines);
void web_lines_disable(web_lines_t *lines);
/* True while the server is on: the observer hub then watches messages. */
bool web_lines_enabled(const web_lines_t *lines);
/* A client looks: lines are kept from now on. */
void web_lines_watch(web_lines_t *lines);
void web_lines_record(web_lines_t *lines, const wsg_conn_t *c, bool incoming, const char *bytes,
                      size_t len);
/* A message from the client (incoming, shown as "> ...") or to it ("< ...");
 * lines NULL (no web server): nothing. */
static inline void web_lines_note(web_lines_t *lines, const wsg_conn_t *c, bool incoming,
                                  const char *bytes, size_t len)
{
    if (lines != NULL && lines->watched) {
        web_lines_record(lines, c, incoming, bytes, len);
    }
}
/* The connection's last lines, oldest first, as an array (empty when none). */
void web_lines_write(const web_lines_t *lines, web_json_t *j, const char *key, const wsg_conn_t *c);
/* "gcl", "binary" or "undetected" (no byte yet on an auto-detecting port). */
const char *web_lines_protocol(const web_lines_t *lines, const wsg_conn_t *c);
/* The observer for devices without the hub's (devices 1.. of a fleet): its
 * context is the web_lines_t. */
const wsg_conn_observer_t *web_lines_observer(void);

#endif
