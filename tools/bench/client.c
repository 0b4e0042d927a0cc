/* SPDX-License-Identifier: BSD-3-Clause */
/* The load generator: round trips, pipelined throughput, AUTOSEND timing. */
#include <arpa/inet.h>
#include <errno.h>
#include <math.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <unistd.h>

#include "bench.h"

#define PIPELINE_DEPTH 32
#define WARMUP_US 200000.0
#define MAX_CLIENTS 128
#define REQUEST "POS?\n"
#define REQUEST_LEN (sizeof(REQUEST) - 1)

/* A socket connected to 127.0.0.1:port, or -1. */
static int try_connect(int type, int port)
{
    int fd = socket(AF_INET, type | SOCK_CLOEXEC, 0);
    struct sockaddr_in sa = {.sin_family = AF_INET, .sin_port = htons((uint16_t)port)};
    sa.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    if (fd >= 0 && connect(fd, (struct sockaddr *)&sa, sizeof(sa)) != 0) {
        close(fd);
        fd = -1;
    }
    return fd;
}

static int connect_socket(int type, int port)
{
    int fd = try_connect(type, port);
    if (fd < 0) {
        die("cannot connect to 127.0.0.1:%d: %s", port, strerror(errno));
    }
    return fd;
}

int try_tcp_connect(int port)
{
    int fd = try_connect(SOCK_STREAM, port);
    int one = 1;
    if (fd >= 0) {
        setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof(one));
    }
    return fd;
}

int tcp_connect(int port)
{
    int fd = connect_socket(SOCK_STREAM, port);
    int one = 1;
    setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof(one));
    return fd;
}

int udp_connect(int port)
{
    return connect_socket(SOCK_DGRAM, port);
}

bool conn_send(conn_t *c, const char *line)
{
    char buf[512];
    size_t len = strlen(line);
    if (len + 1 > sizeof(buf)) {
        return false;
    }
    memcpy(buf, line, len);
    buf[len] = '\n';
    return send(c->fd, buf, len + 1, MSG_NOSIGNAL) == (ssize_t)(len + 1);
}

static bool take_line(conn_t *c, char *out, size_t cap)
{
    char *nl = memchr(c->buf, '\n', c->len);
    if (nl == NULL) {
        return false;
    }
    size_t n = (size_t)(nl - c->buf);
    size_t copy = n < cap - 1 ? n : cap - 1;
    memcpy(out, c->buf, copy);
    out[copy] = '\0';
    c->len -= n + 1;
    memmove(c->buf, nl + 1, c->len);
    return true;
}

bool conn_read_line(conn_t *c, char *out, size_t cap, int timeout_ms)
{
    while (!take_line(c, out, cap)) {
        struct pollfd p = {.fd = c->fd, .events = POLLIN};
        if (c->len == sizeof(c->buf) || poll(&p, 1, timeout_ms) <= 0) {
            return false;
        }
        ssize_t n = recv(c->fd, c->buf + c->len, sizeof(c->buf) - c->len, 0);
        if (n <= 0) {
            return false;
        }
        c->len += (size_t)n;
    }
    return true;
}

bool rtt_tcp(conn_t *c, const char *req, double *us)
{
    char line[256];
    double t0 = now_us();
    if (!conn_send(c, req) || !conn_read_line(c, line, sizeof(line), 2000)) {
        return false;
    }
    *us = now_us() - t0;
    return true;
}

bool rtt_udp(int fd, const char *req, double *us)
{
    char buf[2048];
    size_t len = strlen(req);
    memcpy(buf, req, len);
    buf[len] = '\n';
    double t0 = now_us();
    if (send(fd, buf, len + 1, 0) != (ssize_t)(len + 1)) {
        return false;
    }
    struct pollfd p = {.fd = fd, .events = POLLIN};
    if (poll(&p, 1, 1000) <= 0 || recv(fd, buf, sizeof(buf), 0) <= 0) {
        return false;
    }
    *us = now_us() - t0;
    return true;
}

/* Pipelined load ------------------------------------------------------- */

typedef struct {
    int fd;
    size_t owed;  /* request bytes to send (one request per reply received) */
    size_t phase; /* bytes of a request already sent */
} load_conn_t;

static void send_owed(load_conn_t *c)
{
    static char burst[(PIPELINE_DEPTH * 4 + 1) * REQUEST_LEN];
    static bool filled;
    if (!filled) {
        for (size_t i = 0; i + REQUEST_LEN <= sizeof(burst); i += REQUEST_LEN) {
            memcpy(burst + i, REQUEST, REQUEST_LEN);
        }
        filled = true;
    }
    while (c->owed > 0) {
        size_t want = c->owed;
        want = want > sizeof(burst) - REQUEST_LEN ? sizeof(burst) - REQUEST_LEN : want;
        ssize_t n = send(c->fd, burst + c->phase, want, MSG_DONTWAIT | MSG_NOSIGNAL);
        if (n <= 0) {
            return;
        }
        c->owed -= (size_t)n;
        c->phase = (c->phase + (size_t)n) % REQUEST_LEN;
    }
}

static long receive_replies(load_conn_t *c)
{
    char buf[65536];
    ssize_t n = recv(c->fd, buf, sizeof(buf), MSG_DONTWAIT);
    if (n == 0) {
        die("server closed a pipelined connection");
    }
    long lines = 0;
    for (ssize_t i = 0; i < n; i++) {
        lines += buf[i] == '\n';
    }
    c->owed += (size_t)lines * REQUEST_LEN;
    return lines;
}

static long pump(load_conn_t *conns, struct pollfd *pfd, int clients)
{
    long replies = 0;
    if (poll(pfd, (nfds_t)clients, 1000) <= 0) {
        die("pipelined load stalled");
    }
    for (int i = 0; i < clients; i++) {
        if (pfd[i].revents != 0) {
            replies += receive_replies(&conns[i]);
            send_owed(&conns[i]);
        }
    }
    return replies;
}

double throughput(int port, int clients, double seconds)
{
    load_conn_t conns[MAX_CLIENTS];
    struct pollfd pfd[MAX_CLIENTS];
    for (int i = 0; i < clients; i++) {
        conns[i] = (load_conn_t){.fd = tcp_connect(port), .owed = PIPELINE_DEPTH * REQUEST_LEN};
        pfd[i] = (struct pollfd){.fd = conns[i].fd, .events = POLLIN};
        send_owed(&conns[i]);
    }
    double start = now_us() + WARMUP_US;
    double end = start + seconds * 1e6;
    long replies = 0;
    double t;
    while ((t = now_us()) < end) {
        long got = pump(conns, pfd, clients);
        replies += t >= start ? got : 0;
    }
    for (int i = 0; i < clients; i++) {
        close(conns[i].fd);
    }
    return (double)replies / seconds;
}

/* AUTOSEND timing ------------------------------------------------------- */

typedef struct {
    conn_t conn;
    double last_us;
    int seen;
} sub_t;

static void on_value(sub_t *s, double t, double settle_until, autosend_result_t *r)
{
    const double period = BENCH_PERIOD_MS * 1000.0;
    s->seen++;
    if (s->last_us > 0 && t >= settle_until) {
        double d = t - s->last_us;
        samples_add(&r->error_us, fabs(d - period));
        long skipped = lround(d / period) - 1;
        r->missed += skipped > 0 ? skipped : 0;
        r->lines++;
    }
    s->last_us = t;
}

static void read_values(sub_t *s, double settle_until, autosend_result_t *r)
{
    ssize_t n = recv(s->conn.fd, s->conn.buf + s->conn.len, sizeof(s->conn.buf) - s->conn.len,
                     MSG_DONTWAIT);
    if (n <= 0) {
        return;
    }
    double t = now_us();
    s->conn.len += (size_t)n;
    char line[256];
    while (take_line(&s->conn, line, sizeof(line))) {
        if (line[0] == '@') {
            on_value(s, t, settle_until, r);
        }
    }
}

static void subscribe(sub_t *s, int port)
{
    char line[256];
    memset(s, 0, sizeof(*s));
    s->conn.fd = tcp_connect(port);
    if (!conn_send(&s->conn, "AUTOSEND(\"POS\",10)") ||
        !conn_read_line(&s->conn, line, sizeof(line), 2000) || strcmp(line, "ACK AUTOSEND") != 0) {
        die("AUTOSEND subscription failed: '%s'", line);
    }
}

void autosend_run(int port, int clients, double seconds, autosend_result_t *r)
{
    sub_t subs[MAX_CLIENTS];
    struct pollfd pfd[MAX_CLIENTS];
    samples_init(&r->error_us, 16384);
    r->lines = r->missed = 0;
    for (int i = 0; i < clients; i++) {
        subscribe(&subs[i], port);
        pfd[i] = (struct pollfd){.fd = subs[i].conn.fd, .events = POLLIN};
    }
    double settle = now_us() + 0.5e6;
    double end = settle + seconds * 1e6;
    while (now_us() < end) {
        if (poll(pfd, (nfds_t)clients, 100) <= 0) {
            continue;
        }
        for (int i = 0; i < clients; i++) {
            if (pfd[i].revents != 0) {
                read_values(&subs[i], settle, r);
            }
        }
    }
    r->clients_ok = 0;
    for (int i = 0; i < clients; i++) {
        r->clients_ok += subs[i].seen > 0;
        close(subs[i].conn.fd);
    }
    samples_sort(&r->error_us);
}
