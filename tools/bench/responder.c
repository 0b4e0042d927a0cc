/* SPDX-License-Identifier: BSD-3-Clause */
/* The floor for virtual time through a process: a responder that speaks the
 * part of GCL and of the control channel that the virtual-time cycles use
 * (vtime_ctl.c), and simulates nothing. A GCL command line NAME(...) is
 * answered "ACK NAME"; a control line RUN_UNTIL_DONE(...) is answered with
 * "FIN NAME" on the GCL connection and then RUN_UNTIL_DONE=[t,"done"], its
 * clock moved on by a fixed time per command. It makes the same system
 * calls per command as wsgsim (an epoll_wait and a recv per request, a send
 * per reply), so the same client against it times only the round trips:
 * the most any server can reach on this machine with that client. */
#include <errno.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <stdio.h>
#include <string.h>
#include <sys/epoll.h>
#include <sys/socket.h>
#include <unistd.h>

#include "bench.h"

#define RESPONDER_BUF 1024
#define RESPONDER_NAME_MAX 32

typedef struct {
    int fd; /* -1: not connected */
    size_t len;
    char buf[RESPONDER_BUF];
} responder_conn_t;

typedef struct {
    int epoll_fd;
    int gcl_listen_fd;
    int ctl_listen_fd;
    responder_conn_t gcl;
    responder_conn_t ctl;
    char command[RESPONDER_NAME_MAX]; /* the last GCL command's name */
    double ms_per_command;
    double sim_now_ms;
} responder_t;

static void reply(const responder_conn_t *c, const char *line)
{
    if (c->fd >= 0) {
        send(c->fd, line, strlen(line), MSG_DONTWAIT | MSG_NOSIGNAL);
    }
}

static void on_gcl_line(responder_t *r, const char *line)
{
    size_t name_len = strcspn(line, "(");
    if (line[name_len] != '(' || name_len >= sizeof(r->command)) {
        reply(&r->gcl, "ERR 0 unknown\n");
        return;
    }
    memcpy(r->command, line, name_len);
    r->command[name_len] = '\0';
    char ack[RESPONDER_NAME_MAX + 8];
    snprintf(ack, sizeof(ack), "ACK %s\n", r->command);
    reply(&r->gcl, ack);
}

static void on_ctl_line(responder_t *r, const char *line)
{
    if (strncmp(line, "RUN_UNTIL_DONE(", 15) != 0) {
        reply(&r->ctl, "ERR unknown\n");
        return;
    }
    char fin[RESPONDER_NAME_MAX + 8];
    char done[64];
    r->sim_now_ms += r->ms_per_command;
    snprintf(fin, sizeof(fin), "FIN %s\n", r->command);
    snprintf(done, sizeof(done), "RUN_UNTIL_DONE=[%.3f,\"done\"]\n", r->sim_now_ms);
    reply(&r->gcl, fin); /* as wsgsim: the FIN goes out before the control reply */
    reply(&r->ctl, done);
}

/* Answers every complete line; keeps a partial one for the next read. */
static void on_readable(responder_t *r, responder_conn_t *c)
{
    ssize_t n = recv(c->fd, c->buf + c->len, sizeof(c->buf) - c->len - 1, MSG_DONTWAIT);
    if (n == 0 || (n < 0 && errno != EAGAIN && errno != EINTR)) {
        close(c->fd); /* also leaves the epoll set */
        c->fd = -1;
        c->len = 0;
        return;
    }
    c->len += n > 0 ? (size_t)n : 0u;
    c->buf[c->len] = '\0';
    char *start = c->buf;
    char *nl;
    while ((nl = strchr(start, '\n')) != NULL) {
        *nl = '\0';
        if (c == &r->gcl) {
            on_gcl_line(r, start);
        } else {
            on_ctl_line(r, start);
        }
        start = nl + 1;
    }
    c->len = strlen(start);
    memmove(c->buf, start, c->len);
    if (c->len == sizeof(c->buf) - 1) {
        c->len = 0; /* an overlong line: forget it */
    }
}

/* One client per listener: a new connection replaces the last. */
static void on_accept(responder_t *r, int listen_fd, responder_conn_t *c)
{
    int fd = accept4(listen_fd, NULL, NULL, SOCK_NONBLOCK | SOCK_CLOEXEC);
    if (fd < 0) {
        return;
    }
    struct epoll_event ev = {.events = EPOLLIN, .data.fd = fd};
    if (epoll_ctl(r->epoll_fd, EPOLL_CTL_ADD, fd, &ev) != 0) {
        close(fd);
        return;
    }
    int one = 1; /* as wsgsim does: no Nagle delay on replies */
    setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof(one));
    if (c->fd >= 0) {
        close(c->fd);
    }
    c->fd = fd;
    c->len = 0;
}

static void dispatch(responder_t *r, int fd)
{
    if (fd == r->gcl_listen_fd) {
        on_accept(r, fd, &r->gcl);
    } else if (fd == r->ctl_listen_fd) {
        on_accept(r, fd, &r->ctl);
    } else if (fd == r->gcl.fd) {
        on_readable(r, &r->gcl);
    } else if (fd == r->ctl.fd) {
        on_readable(r, &r->ctl);
    }
}

void responder_server_run(int gcl_listen_fd, int ctl_listen_fd, double ms_per_command)
{
    responder_t r = {.gcl_listen_fd = gcl_listen_fd,
                     .ctl_listen_fd = ctl_listen_fd,
                     .gcl.fd = -1,
                     .ctl.fd = -1,
                     .ms_per_command = ms_per_command};
    r.epoll_fd = epoll_for_two(gcl_listen_fd, ctl_listen_fd, "responder");
    struct epoll_event events[8];
    for (;;) {
        int n = epoll_wait(r.epoll_fd, events, 8, -1);
        for (int i = 0; i < n; i++) {
            dispatch(&r, events[i].data.fd);
        }
    }
}
