/* SPDX-License-Identifier: BSD-3-Clause */
/* The web connections whose request is still arriving (docs/web.md,
 * "Slow clients"): a client that trickles its request a byte at a time
 * (slowloris) may hold only a few connections, and only for a while.
 *
 * A connection is arriving from the moment it opens, and again from the end
 * of each reply (keep-alive), until its request, header and body, has been
 * read and is answered. Each client address (an IPv6 client's /64) may have
 * WEB_INTAKE_PER_ADDRESS arriving connections; a further one is refused as
 * it is accepted. An arriving connection still arriving after the request
 * deadline (wall clock) is shut down; MHD then sees it end and closes it.
 * Connections being answered (an event stream, a reply being sent) are not
 * arriving and count against neither rule. */
#ifndef HOST_WEB_INTAKE_H
#define HOST_WEB_INTAKE_H

#include <stdbool.h>
#include <stdint.h>
#include <sys/socket.h>

#define WEB_INTAKE_PER_ADDRESS 16u
/* The web server's connection limit: the records are a fixed pool. Room
 * for 200 event streams (10 from each of 20 addresses) and the requests
 * beside them; an idle connection costs MHD its 16 KiB pool. */
#define WEB_INTAKE_CONNECTIONS_MAX 256u

typedef struct web_intake_conn web_intake_conn_t;
/* One web server's connection records. */
typedef struct web_intake web_intake_t;

/* Empty, with no deadline yet (web_intake_reset() sets one); NULL: out of
 * memory. */
web_intake_t *web_intake_create(void);
void web_intake_destroy(web_intake_t *intake);
/* Starts with no connection and this deadline for a request to arrive. */
void web_intake_reset(web_intake_t *intake, uint64_t deadline_ns);
/* Whether a client at addr may open one more connection. */
bool web_intake_admits(const web_intake_t *intake, const struct sockaddr *addr);
/* A connection was opened on socket fd by addr at now; its record (NULL
 * when the pool is full: the caller closes it). */
web_intake_conn_t *web_intake_open(web_intake_t *intake, int fd, const struct sockaddr *addr,
                                   uint64_t now);
/* Its request has arrived in full (it is being answered). */
void web_intake_arrived(web_intake_t *intake, web_intake_conn_t *conn);
/* Its reply is done: it waits for its next request from now. */
void web_intake_waiting(web_intake_t *intake, web_intake_conn_t *conn, uint64_t now);
/* Its request's URL or query held an encoded NUL (%00), which the URL a
 * route sees would silently end at: noted while MHD decodes the request
 * line, taken (and cleared) when the request is handled. */
void web_intake_note_nul(web_intake_conn_t *conn);
bool web_intake_take_nul(web_intake_conn_t *conn);
/* It is closed; its record is free. */
void web_intake_close(web_intake_t *intake, web_intake_conn_t *conn);
/* Shuts down every connection whose request is late at now; the number. */
unsigned web_intake_cut_late(web_intake_t *intake, uint64_t now);
/* When the oldest arriving request is due (monotonic ns), 0: none. */
uint64_t web_intake_next_due_ns(const web_intake_t *intake);

#endif
