#include "tcp_server.h"

#include <errno.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <string.h>
#include <sys/socket.h>
#include <unistd.h>

#include "gripper.h"
#include "log.h"
#include "loop.h"
#include "net.h"
#include "outq.h"

#define CLIENTS_MAX 128
#define OUTQ_BYTES (16u * 1024u)
/* Above this fill level AUTOSEND lines are dropped to keep room for replies. */
#define OUTQ_AUTOSEND_LIMIT (OUTQ_BYTES / 2u)
#define READ_CHUNK 4096

typedef struct {
    bool in_use;
    int fd;
    wsg_session_t *session;
    outq_t outq;
    bool dead; /* failed or overflowed: close at the next reap */
    unsigned long dropped_autosend;
    char peer[64];
} tcp_client_t;

static struct {
    int listen_fd;
    int max_clients;
    tcp_client_t clients[CLIENTS_MAX];
} tcp = {.listen_fd = -1};

static unsigned open_count(void)
{
    unsigned n = 0;
    for (unsigned i = 0; i < CLIENTS_MAX; i++) {
        n += tcp.clients[i].in_use ? 1u : 0u;
    }
    return n;
}

static void update_events(tcp_client_t *c)
{
    loop_set_events(c->fd, (short)(POLLIN | (outq_empty(&c->outq) ? 0 : POLLOUT)));
}

/* Sends one line with one send(); returns bytes sent, or -1 on a fatal error. */
static ssize_t send_line(tcp_client_t *c, const char *line, size_t len)
{
    ssize_t sent = send(c->fd, line, len, MSG_NOSIGNAL | MSG_DONTWAIT);
    if (sent < 0 && (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR)) {
        return 0;
    }
    return sent;
}

static void enqueue(tcp_client_t *c, const char *line, size_t len, wsg_line_kind_t kind)
{
    bool crowded = outq_used(&c->outq) >= OUTQ_AUTOSEND_LIMIT;
    if (kind == WSG_LINE_AUTOSEND && crowded) {
        c->dropped_autosend++;
        return;
    }
    if (!outq_push(&c->outq, line, len)) {
        if (kind == WSG_LINE_AUTOSEND) {
            c->dropped_autosend++;
            return;
        }
        host_logf(HAL_LOG_WARN, "tcp %s: not reading its replies; disconnected", c->peer);
        c->dead = true;
        return;
    }
    update_events(c);
}

static void write_line(void *ctx, const char *line, size_t len, wsg_line_kind_t kind)
{
    tcp_client_t *c = ctx;
    if (c->dead) {
        return;
    }
    if (outq_empty(&c->outq)) {
        ssize_t sent = send_line(c, line, len);
        if (sent < 0) {
            c->dead = true;
            return;
        }
        if ((size_t)sent == len) {
            return;
        }
        line += sent;
        len -= (size_t)sent;
        kind = WSG_LINE_REPLY; /* a started line must be finished */
    }
    enqueue(c, line, len, kind);
}

static const wsg_session_io_t tcp_io = {.write_line = write_line};

static void flush(tcp_client_t *c)
{
    char line[OUTQ_BYTES];
    while (!outq_empty(&c->outq)) {
        size_t len = outq_peek(&c->outq, line, sizeof(line));
        ssize_t sent = send_line(c, line, len);
        if (sent < 0) {
            c->dead = true;
            return;
        }
        if ((size_t)sent < len) {
            outq_trim_front(&c->outq, (size_t)sent);
            break;
        }
        outq_pop(&c->outq);
    }
    update_events(c);
}

static void close_client(tcp_client_t *c)
{
    wsg_close_reason_t reason =
        wsg_session_wants_close(c->session) ? WSG_CLOSE_ANNOUNCED : WSG_CLOSE_DROPPED;
    host_logf(HAL_LOG_INFO, "tcp %s: closed%s", c->peer,
              reason == WSG_CLOSE_DROPPED ? " without BYE" : "");
    if (c->dropped_autosend > 0) {
        host_logf(HAL_LOG_INFO, "tcp %s: %lu AUTOSEND lines dropped (client not reading)", c->peer,
                  c->dropped_autosend);
    }
    loop_unwatch(c->fd);
    close(c->fd);
    wsg_session_close(gripper_device(), c->session, reason);
    outq_free(&c->outq);
    c->in_use = false;
}

static void on_client(void *ctx, int fd, short revents)
{
    tcp_client_t *c = ctx;
    (void)fd;
    if ((revents & POLLOUT) != 0) {
        flush(c);
    }
    if ((revents & (POLLIN | POLLHUP | POLLERR)) == 0 || c->dead) {
        return;
    }
    uint8_t buf[READ_CHUNK];
    ssize_t n = recv(c->fd, buf, sizeof(buf), MSG_DONTWAIT);
    if (n > 0) {
        gripper_feed(c->session, buf, (size_t)n, 0);
    } else if (n == 0 || (errno != EAGAIN && errno != EINTR)) {
        c->dead = true;
    }
}

static tcp_client_t *free_slot(void)
{
    if ((int)open_count() >= tcp.max_clients) {
        return NULL;
    }
    for (unsigned i = 0; i < CLIENTS_MAX; i++) {
        if (!tcp.clients[i].in_use) {
            return &tcp.clients[i];
        }
    }
    return NULL;
}

static bool setup_client(tcp_client_t *c, int fd, const struct sockaddr_storage *ss)
{
    memset(c, 0, sizeof(*c));
    c->fd = fd;
    net_format_peer(ss, c->peer, sizeof(c->peer));
    int one = 1;
    setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof(one));
    if (!outq_init(&c->outq, OUTQ_BYTES)) {
        return false;
    }
    c->session = wsg_session_open(gripper_device(), WSG_TRANSPORT_STREAM, &tcp_io, c);
    if (c->session == NULL) {
        outq_free(&c->outq);
        return false;
    }
    if (!loop_watch(fd, POLLIN, on_client, c)) {
        wsg_session_close(gripper_device(), c->session, WSG_CLOSE_ANNOUNCED);
        outq_free(&c->outq);
        return false;
    }
    c->in_use = true;
    return true;
}

static void on_accept(void *ctx, int fd, short revents)
{
    (void)ctx;
    (void)revents;
    struct sockaddr_storage ss;
    socklen_t len = sizeof(ss);
    int client_fd = accept4(fd, (struct sockaddr *)&ss, &len, SOCK_NONBLOCK | SOCK_CLOEXEC);
    if (client_fd < 0) {
        return;
    }
    tcp_client_t *c = free_slot();
    if (c == NULL || !setup_client(c, client_fd, &ss)) {
        char peer[64];
        net_format_peer(&ss, peer, sizeof(peer));
        host_logf(HAL_LOG_WARN, "tcp %s: refused, %d clients connected (--max-clients)", peer,
                  tcp.max_clients);
        close(client_fd);
        return;
    }
    host_logf(HAL_LOG_INFO, "tcp %s: connected", c->peer);
}

bool tcp_server_start(const char *addr, int port, int max_clients)
{
    tcp.listen_fd = net_listen(SOCK_STREAM, addr, port);
    tcp.max_clients = max_clients;
    return tcp.listen_fd >= 0 && loop_watch(tcp.listen_fd, POLLIN, on_accept, NULL);
}

int tcp_server_port(void)
{
    return tcp.listen_fd >= 0 ? net_local_port(tcp.listen_fd) : -1;
}

void tcp_server_reap(void)
{
    for (unsigned i = 0; i < CLIENTS_MAX; i++) {
        tcp_client_t *c = &tcp.clients[i];
        bool said_bye = c->in_use && wsg_session_wants_close(c->session);
        if (c->in_use && (c->dead || (said_bye && outq_empty(&c->outq)))) {
            close_client(c);
        }
    }
}

bool tcp_server_cut(const wsg_session_t *session)
{
    for (unsigned i = 0; i < CLIENTS_MAX; i++) {
        tcp_client_t *c = &tcp.clients[i];
        if (c->in_use && c->session == session) {
            struct linger abort_close = {.l_onoff = 1, .l_linger = 0};
            setsockopt(c->fd, SOL_SOCKET, SO_LINGER, &abort_close, sizeof(abort_close));
            host_logf(HAL_LOG_WARN, "tcp %s: connection cut (control channel)", c->peer);
            close_client(c);
            return true;
        }
    }
    return false;
}

void tcp_server_close_all(void)
{
    for (unsigned i = 0; i < CLIENTS_MAX; i++) {
        if (tcp.clients[i].in_use) {
            close_client(&tcp.clients[i]);
        }
    }
}

void tcp_server_stop(void)
{
    tcp_server_close_all();
    if (tcp.listen_fd >= 0) {
        loop_unwatch(tcp.listen_fd);
        close(tcp.listen_fd);
        tcp.listen_fd = -1;
    }
}
