/* SPDX-License-Identifier: BSD-3-Clause */
/* A listening TCP socket on the event loop that backs off, instead of
 * spinning, when the process runs out of descriptors: the waiting client
 * stays in the backlog and the listener is polled again after a short wait
 * or as soon as its owner frees a descriptor. */
#ifndef HOST_LISTENER_H
#define HOST_LISTENER_H

#include <stdbool.h>
#include <stdint.h>
#include <sys/socket.h>

#include "loop.h"
#include "net.h"

typedef struct {
    host_loop_t *loop; /* the loop it is watched on */
    int fd;
    int port;         /* the port it listens on, asked once at start */
    const char *name; /* for the log: "tcp", "control" */
    bool starved;     /* out of descriptors: not polled until retry_ns */
    uint64_t retry_ns;
} listener_t;

/* Listens on addr:port (a socket of net's) and watches it on loop with
 * on_accept. */
bool listener_start(listener_t *l, host_loop_t *loop, net_t *net, const char *name,
                    const char *addr, int port, loop_callback_t on_accept, void *ctx);
/* accept4() for on_accept: the new descriptor, or -1 (out of descriptors:
 * the listener is paused and the episode logged once). */
int listener_accept(listener_t *l, struct sockaddr_storage *peer, socklen_t *peer_len);
/* The owner closed a descriptor: a paused listener may try again at once. */
void listener_fd_freed(listener_t *l);
/* Once per loop pass: polls a paused listener again when its wait is over. */
void listener_resume_when_due(listener_t *l);
void listener_stop(listener_t *l);

#endif
