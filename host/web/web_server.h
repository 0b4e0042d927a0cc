/* SPDX-License-Identifier: BSD-3-Clause */
/* The device's web interface (issue 13, docs/web.md): the page and its JSON
 * API over HTTP, served by libmicrohttpd from the host's event loop.
 *
 * The hand-off: MHD runs in its external-epoll mode (MHD_USE_EPOLL, no
 * thread of its own). Its epoll descriptor is one watch in host/os/loop.c;
 * when it is readable the loop calls MHD_run(), which serves every ready
 * connection without blocking. MHD's own timeouts (MHD_get_timeout) and the
 * event streams' 25 Hz tick are wall-clock wake-ups (loop_wake_at_wall),
 * run by web_server_poll() after each wait: the simulated clock may be
 * paused, the page's stream and a slow client's timeout are not. */
#ifndef HOST_WEB_SERVER_H
#define HOST_WEB_SERVER_H

#include <stdbool.h>

#include "loop.h"
#include "net.h"
#include "options.h"
#include "simctl/control.h"

typedef struct web_server web_server_t;
struct web_lines;

/* Off, holding nothing yet; NULL: out of memory. */
web_server_t *web_server_create(void);
/* Stops it (when on) and frees it; NULL: nothing. */
void web_server_destroy(web_server_t *web);
/* Starts the server on opts->http_bind (or opts->bind_addr) port
 * opts->http_port; off when the port is 0. False (logged) when the port or
 * the address was given and cannot be had; the default, when taken, is
 * skipped with a warning. The simulation routes run their commands on sim;
 * the pages show fleet's devices. The socket is one of net's, watched on
 * loop. */
struct fleet;
bool web_server_start(web_server_t *web, host_loop_t *loop, net_t *net, const host_options_t *opts,
                      simctl_t *sim, struct fleet *fleet);
/* After every loop_wait(): runs what is due on the wall clock. Costs one
 * test when nothing is scheduled. */
void web_server_poll(web_server_t *web);
/* ", web page http://ADDR:PORT/" for the ready line (a URL to open: the
 * loopback address for a wildcard bind), or "" when off. */
const char *web_server_describe(const web_server_t *web);
/* The port served, or -1. */
int web_server_port(const web_server_t *web);
void web_server_stop(web_server_t *web);
/* The page's connection lines, NULL when the server is off: main attaches
 * them to every device (web_lines_attach). */
struct web_lines *web_server_lines(web_server_t *web);

#endif
