/* SPDX-License-Identifier: BSD-3-Clause */
#include "listener.h"

#include <errno.h>
#include <poll.h>
#include <string.h>
#include <unistd.h>

#include "log.h"
#include "net.h"

#define RETRY_NS 100000000u /* 100 ms between accept() attempts while starved */

/* The option that moves a listener's port, for its error: the control
 * channel's, or a device's GCL port. */
static const char *port_option(const char *name)
{
    return strcmp(name, "control") == 0 ? "--sim-port" : "--tcp-port";
}

bool listener_start(listener_t *l, host_loop_t *loop, net_t *net, const char *name,
                    const char *addr, int port, loop_callback_t on_accept, void *ctx)
{
    int fd = net_listen_for(net, SOCK_STREAM, addr, port, port_option(name));
    *l = (listener_t){.loop = loop, .fd = fd, .name = name};
    l->port = l->fd >= 0 ? net_local_port(l->fd) : -1;
    return l->fd >= 0 && loop_watch(loop, l->fd, POLLIN, on_accept, ctx);
}

static bool out_of_descriptors(int err)
{
    return err == EMFILE || err == ENFILE || err == ENOBUFS || err == ENOMEM;
}

static void pause_listener(listener_t *l, int err)
{
    if (!l->starved) {
        l->starved = true;
        host_logf(HAL_LOG_ERROR,
                  "%s: cannot accept a connection: %s; out of descriptors, waiting "
                  "clients wait (see ulimit -n)",
                  l->name, strerror(err));
    }
    loop_set_events(l->loop, l->fd, 0);
    l->retry_ns = loop_monotonic_ns() + RETRY_NS;
    loop_wake_at_wall(l->loop, l->retry_ns);
}

int listener_accept(listener_t *l, struct sockaddr_storage *peer, socklen_t *peer_len)
{
    int fd = accept4(l->fd, (struct sockaddr *)peer, peer_len, SOCK_NONBLOCK | SOCK_CLOEXEC);
    if (fd < 0) {
        if (out_of_descriptors(errno)) {
            pause_listener(l, errno);
        }
        return -1;
    }
    if (l->starved) {
        l->starved = false;
        host_logf(HAL_LOG_INFO, "%s: accepting connections again", l->name);
    }
    return fd;
}

void listener_fd_freed(listener_t *l)
{
    l->retry_ns = 0;
}

void listener_resume_when_due(listener_t *l)
{
    if (l->fd >= 0 && l->starved && loop_monotonic_ns() >= l->retry_ns) {
        loop_set_events(l->loop, l->fd, POLLIN);
    }
}

void listener_stop(listener_t *l)
{
    if (l->fd >= 0) {
        loop_unwatch(l->loop, l->fd);
        close(l->fd);
        l->fd = -1;
    }
}
