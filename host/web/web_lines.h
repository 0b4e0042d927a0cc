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

#include "json_writer.h"
#include "wsg/wsg_conn.h"

#define WEB_LINES_KEPT 8

typedef struct web_lines_ring web_lines_ring_t;
struct web_lines_device;

/* The lines of one web server (embedded in its routes' state). */
typedef struct web_lines {
    web_lines_ring_t *rings;          /* the table while the server is on, else NULL */
    bool watched;                     /* a client looked: the devices are observed */
    struct web_lines_device *devices; /* one message observer per device */
    unsigned count;
} web_lines_t;

/* The table, for a fleet of `devices`. */
void web_lines_enable(web_lines_t *lines, unsigned devices);
/* Leaves the devices it observes (they must still exist: the web server
 * stops before the fleet) and frees the table. */
void web_lines_disable(web_lines_t *lines);
bool web_lines_enabled(const web_lines_t *lines);
/* Keeps device `index`'s lines (below the enable's count) from the first
 * look on; nothing for NULL or a table that is off. */
void web_lines_attach(web_lines_t *lines, wsg_device_t *dev, unsigned index);
/* A client looks: lines are kept from now on, on every attached device
 * (O(devices), once). */
void web_lines_watch(web_lines_t *lines);
/* The connection's last lines, oldest first, as an array (empty when none). */
void web_lines_write(const web_lines_t *lines, json_writer_t *j, const char *key,
                     const wsg_conn_t *c);
/* "gcl", "binary" or "undetected" (no byte yet on an auto-detecting port). */
const char *web_lines_protocol(const web_lines_t *lines, const wsg_conn_t *c);

#endif
