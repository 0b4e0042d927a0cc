/* SPDX-License-Identifier: BSD-3-Clause */
/* The TCP servers' side of accepting: the listening sockets, whose
 * connection a new one is (a shared listener), its slot (--max-clients, the
 * stalled-slot rule) and the refusals; a connection's own life is
 * tcp_server.c's. */
#include <netinet/in.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <unistd.h>

#include "listener.h"
#include "log.h"
#include "net.h"
#include "tcp_client.h"
#include "tcp_server.h"

/* With every slot taken, a connection that has completed no command (line
 * or frame) for this long, and is stuck inside one or never completed any,
 * gives its slot to a newcomer: real clients speak first, and finish what
 * they start. A connection quiet after a whole command keeps its slot. */
#define STALLED_GRACE_US (30u * 1000000u)

static void reclaim_stalled_slot(const tcp_server_t *s)
{
    tcp_client_t *c = tcp_stalled_connection(s, STALLED_GRACE_US);
    if (c != NULL) {
        host_log_peer(
            HAL_LOG_INFO, "tcp %s: no whole command for %u s (%s); slot given to a waiting client",
            c->peer, (unsigned)(STALLED_GRACE_US / 1000000u),
            c->messages_in == 0 && c->heard_us == c->connected_us ? "silent" : "stuck inside one");
        c->expired = true;
        tcp_client_close(c);
    }
}

/* Storage for a new connection, or NULL when --max-clients are open. */
static tcp_client_t *new_client(tcp_server_t *s)
{
    if ((int)s->open >= s->max_clients) {
        reclaim_stalled_slot(s);
    }
    if ((int)s->open >= s->max_clients) {
        return NULL;
    }
    tcp_client_t *c = calloc(1, sizeof(*c));
    if (c != NULL) {
        c->server = s;
    }
    return c;
}

static void wait_for_descriptors(tcp_server_t *s)
{
    tcp_servers_t *tcp = s->set;
    if (s->listener->starved && !s->waits_for_fds) {
        s->waits_for_fds = true;
        list_push_front(&tcp->waiting, &s->waiting_link);
    }
}

/* A shared listener's connection to an address no device owns: reset. */
static void refuse_foreign(int client_fd, const struct sockaddr_storage *peer)
{
    char name[64];
    struct linger abort_close = {.l_onoff = 1, .l_linger = 0};
    setsockopt(client_fd, SOL_SOCKET, SO_LINGER, &abort_close, sizeof(abort_close));
    close(client_fd);
    net_format_peer(peer, name, sizeof(name));
    host_log_peer(HAL_LOG_WARN, "tcp %s: refused, its destination is no device's address", name);
}

/* The server a new connection belongs to: s itself, or for a shared
 * listener the one its route() names (NULL: refused). */
static tcp_server_t *owner_of(tcp_server_t *s, int client_fd)
{
    struct sockaddr_storage local;
    socklen_t len = sizeof(local);
    if (s->route == NULL) {
        return s;
    }
    memset(&local, 0, sizeof(local));
    if (getsockname(client_fd, (struct sockaddr *)&local, &len) != 0) {
        return NULL;
    }
    return s->route(s->route_ctx, &local);
}

static void on_accept(void *ctx, int fd, short revents)
{
    tcp_server_t *front = ctx;
    (void)fd;
    (void)revents;
    struct sockaddr_storage ss;
    socklen_t len = sizeof(ss);
    int client_fd = listener_accept(front->listener, &ss, &len);
    if (client_fd < 0) {
        wait_for_descriptors(front);
        return;
    }
    tcp_server_t *s = owner_of(front, client_fd);
    if (s == NULL) {
        refuse_foreign(client_fd, &ss);
        return;
    }
    tcp_client_t *c = new_client(s);
    if (c == NULL || !tcp_client_setup(c, client_fd, &ss)) {
        free(c);
        char peer[64];
        net_format_peer(&ss, peer, sizeof(peer));
        host_log_peer(HAL_LOG_WARN, "tcp %s: refused, %d clients connected (--max-clients)", peer,
                      s->max_clients);
        close(client_fd);
        return;
    }
    host_log_peer(HAL_LOG_INFO, "tcp %s: connected", c->peer);
}

bool tcp_server_start(tcp_server_t *s, tcp_servers_t *set, gripper_t *g, const char *addr, int port,
                      int max_clients, int idle_timeout_s)
{
    s->set = set;
    tcp_server_attach(s, g, s, max_clients, idle_timeout_s);
    return listener_start(&s->own, set->loop, set->net, "tcp", addr, port, on_accept, s);
}

bool tcp_server_start_shared(tcp_server_t *s, tcp_servers_t *set, const char *addr, int port,
                             tcp_route_t route, void *ctx)
{
    s->set = set;
    tcp_server_attach(s, NULL, s, 0, 0);
    s->route = route;
    s->route_ctx = ctx;
    return listener_start(&s->own, set->loop, set->net, "tcp", addr, port, on_accept, s);
}

void tcp_server_attach(tcp_server_t *s, gripper_t *g, tcp_server_t *front, int max_clients,
                       int idle_timeout_s)
{
    tcp_servers_t *set = front->set;
    memset(s, 0, sizeof(*s));
    s->set = set;
    s->own.fd = -1;
    s->listener = &front->own;
    s->gripper = g;
    s->max_clients = max_clients;
    s->idle_timeout_us = (uint64_t)idle_timeout_s * 1000000u;
}

int tcp_server_port(const tcp_server_t *s)
{
    return s->listener != NULL && s->listener->fd >= 0 ? s->listener->port : -1;
}
