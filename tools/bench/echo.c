/* SPDX-License-Identifier: BSD-3-Clause */
/* The baseline: a minimal single-threaded line server on loopback. Every
 * TCP line is sent back with its own send() (one line in, one line out, as
 * wsgsim answers), every UDP datagram is returned as it came. A line
 * starting with "AUTOSEND" subscribes the connection to a line every
 * BENCH_PERIOD_MS, scheduled on absolute deadlines: the timer limit of the
 * machine for the AUTOSEND measurement. */
#include <errno.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <time.h>
#include <unistd.h>

#include "bench.h"

#define ECHO_CLIENTS 256
#define ECHO_BUF 8192

typedef struct {
    int fd;
    size_t len;
    double next_tick_us; /* 0: not subscribed */
    char buf[ECHO_BUF];
} echo_client_t;

static echo_client_t clients[ECHO_CLIENTS];
static struct pollfd fds[ECHO_CLIENTS + 2];
static int fd_client[ECHO_CLIENTS + 2]; /* which client each pollfd is */

static void reply(echo_client_t *c, const char *line, size_t len)
{
    static const char ack[] = "ACK AUTOSEND\n";
    if (len >= 8 && memcmp(line, "AUTOSEND", 8) == 0) {
        c->next_tick_us = now_us();
        send(c->fd, ack, sizeof(ack) - 1, MSG_DONTWAIT | MSG_NOSIGNAL);
        return;
    }
    send(c->fd, line, len, MSG_DONTWAIT | MSG_NOSIGNAL);
}

static void drop_client(echo_client_t *c)
{
    close(c->fd);
    c->fd = -1;
}

static void on_readable(echo_client_t *c)
{
    ssize_t n = recv(c->fd, c->buf + c->len, sizeof(c->buf) - c->len, MSG_DONTWAIT);
    if (n == 0 || (n < 0 && errno != EAGAIN && errno != EINTR)) {
        drop_client(c);
        return;
    }
    if (n < 0) {
        return;
    }
    c->len += (size_t)n;
    size_t start = 0;
    for (size_t i = 0; i < c->len; i++) {
        if (c->buf[i] == '\n') {
            reply(c, c->buf + start, i + 1 - start);
            start = i + 1;
        }
    }
    memmove(c->buf, c->buf + start, c->len - start);
    c->len -= start;
    if (c->len == sizeof(c->buf)) {
        c->len = 0; /* an overlong line: forget it */
    }
}

static void on_accept(int listen_fd)
{
    int fd = accept4(listen_fd, NULL, NULL, SOCK_NONBLOCK | SOCK_CLOEXEC);
    if (fd < 0) {
        return;
    }
    int one = 1; /* as wsgsim does: no Nagle delay on replies */
    setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof(one));
    for (int i = 0; i < ECHO_CLIENTS; i++) {
        if (clients[i].fd < 0) {
            clients[i].fd = fd;
            clients[i].len = 0;
            clients[i].next_tick_us = 0;
            return;
        }
    }
    close(fd);
}

static void on_datagram(int fd)
{
    char buf[65536];
    struct sockaddr_storage ss;
    socklen_t len = sizeof(ss);
    ssize_t n = recvfrom(fd, buf, sizeof(buf), MSG_DONTWAIT, (struct sockaddr *)&ss, &len);
    if (n >= 0) {
        sendto(fd, buf, (size_t)n, MSG_DONTWAIT, (struct sockaddr *)&ss, len);
    }
}

/* Sends due ticks; returns the next deadline (or a large value). */
static double run_ticks(void)
{
    static const char tick[] = "@POS=55.0\n";
    double now = now_us();
    double next = now + 1e6;
    for (int i = 0; i < ECHO_CLIENTS; i++) {
        echo_client_t *c = &clients[i];
        if (c->fd < 0 || c->next_tick_us == 0) {
            continue;
        }
        if (c->next_tick_us <= now) {
            send(c->fd, tick, sizeof(tick) - 1, MSG_DONTWAIT | MSG_NOSIGNAL);
            c->next_tick_us += BENCH_PERIOD_MS * 1000.0;
            while (c->next_tick_us <= now) {
                c->next_tick_us += BENCH_PERIOD_MS * 1000.0;
            }
        }
        next = c->next_tick_us < next ? c->next_tick_us : next;
    }
    return next;
}

static void wait_events(int tcp_fd, int udp_fd, double deadline)
{
    nfds_t n = 0;
    fds[n++] = (struct pollfd){.fd = tcp_fd, .events = POLLIN};
    fds[n++] = (struct pollfd){.fd = udp_fd, .events = POLLIN};
    for (int i = 0; i < ECHO_CLIENTS; i++) {
        if (clients[i].fd >= 0) {
            fd_client[n] = i;
            fds[n++] = (struct pollfd){.fd = clients[i].fd, .events = POLLIN};
        }
    }
    double left = deadline - now_us();
    left = left < 0 ? 0 : left;
    struct timespec ts = {.tv_sec = (time_t)(left / 1e6),
                          .tv_nsec = (long)((left - (double)(time_t)(left / 1e6) * 1e6) * 1e3)};
    if (ppoll(fds, n, &ts, NULL) <= 0) {
        return;
    }
    if (fds[0].revents != 0) {
        on_accept(tcp_fd);
    }
    if (fds[1].revents != 0) {
        on_datagram(udp_fd);
    }
    for (nfds_t k = 2; k < n; k++) {
        if (fds[k].revents != 0) {
            on_readable(&clients[fd_client[k]]);
        }
    }
}

void echo_server_run(int tcp_fd, int udp_fd)
{
    for (int i = 0; i < ECHO_CLIENTS; i++) {
        clients[i].fd = -1;
    }
    for (;;) {
        wait_events(tcp_fd, udp_fd, run_ticks());
    }
}
