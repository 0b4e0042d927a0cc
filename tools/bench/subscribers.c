/* SPDX-License-Identifier: BSD-3-Clause */
/* Many AUTOSEND subscribers at 10 ms. The subscriptions are made while the
 * clock is paused, so they all share one phase: the distinct deadlines are
 * one per period for them (plus the finger bus's own 10 ms cycle), and a
 * server that wakes only for distinct deadlines wakes at most twice per
 * period however many subscribers it has. Missed periods are the server's
 * own count (STATE? on the control channel, "missed" per subscription),
 * which unlike arrival gaps at the client does not include the client's
 * scheduling; the gaps are reported too. */
#include <errno.h>
#include <math.h>
#include <poll.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <unistd.h>

#include "bench.h"

#define SUBSCRIBERS_MAX 128
#define SETTLE_US 500000.0
#define STATE_BYTES (1024 * 1024)

typedef struct {
    conn_t conn;
    double last_us;
    long values;
} subscriber_t;

static void subscribe(subscriber_t *s, int port)
{
    char line[256] = "";
    memset(s, 0, sizeof(*s));
    s->conn.fd = tcp_connect(port);
    if (!conn_send(&s->conn, "AUTOSEND(\"POS\",10)") ||
        !conn_read_line(&s->conn, line, sizeof(line), 5000) || strcmp(line, "ACK AUTOSEND") != 0) {
        die("AUTOSEND subscription failed: '%s'", line);
    }
}

/* Reads what arrived; counts gaps of whole periods once measuring. */
static void read_values(subscriber_t *s, bool measuring, subscribers_result_t *r)
{
    ssize_t n = recv(s->conn.fd, s->conn.buf + s->conn.len, sizeof(s->conn.buf) - s->conn.len,
                     MSG_DONTWAIT);
    if (n <= 0) {
        return;
    }
    double t = now_us();
    s->conn.len += (size_t)n;
    char line[256];
    while (conn_read_line(&s->conn, line, sizeof(line), 0)) {
        if (line[0] != '@') {
            continue;
        }
        if (measuring && s->last_us > 0) {
            long skipped = lround((t - s->last_us) / (BENCH_PERIOD_MS * 1000.0)) - 1;
            r->client_gaps += skipped > 0 ? skipped : 0;
            r->lines++;
            s->values++;
        }
        s->last_us = t;
    }
}

static void read_until(subscriber_t *subs, int clients, double until_us, bool measuring,
                       subscribers_result_t *r)
{
    struct pollfd pfd[SUBSCRIBERS_MAX];
    for (int i = 0; i < clients; i++) {
        pfd[i] = (struct pollfd){.fd = subs[i].conn.fd, .events = POLLIN};
    }
    while (now_us() < until_us) {
        if (poll(pfd, (nfds_t)clients, 100) <= 0) {
            continue;
        }
        for (int i = 0; i < clients; i++) {
            if (pfd[i].revents != 0) {
                read_values(&subs[i], measuring, r);
            }
        }
    }
}

/* Sends a control command and reads its one reply line (any length). */
static char *control(int fd, const char *cmd)
{
    char *reply = malloc(STATE_BYTES);
    size_t len = 0;
    size_t cmd_len = strlen(cmd);
    if (reply == NULL || send(fd, cmd, cmd_len, MSG_NOSIGNAL) != (ssize_t)cmd_len) {
        die("control channel: cannot send %s", cmd);
    }
    while (len == 0 || reply[len - 1] != '\n') {
        struct pollfd p = {.fd = fd, .events = POLLIN};
        ssize_t n = len + 1 < STATE_BYTES && poll(&p, 1, 10000) > 0
                        ? recv(fd, reply + len, STATE_BYTES - 1 - len, 0)
                        : -1;
        if (n <= 0) {
            die("control channel: no whole reply to %s", cmd);
        }
        len += (size_t)n;
    }
    reply[len] = '\0';
    return reply;
}

static long sum_missed(const char *state)
{
    long missed = 0;
    int found = 0;
    for (const char *at = strstr(state, "\"missed\":"); at != NULL;
         at = strstr(at + 1, "\"missed\":")) {
        missed += strtol(at + 9, NULL, 10);
        found++;
    }
    if (strncmp(state, "STATE=", 6) != 0 || found == 0) {
        die("STATE? shows no AUTOSEND subscriptions: %.80s", state);
    }
    return missed;
}

void subscribers_run(const char *wsgsim, const char *log_path, int clients, double seconds,
                     subscribers_result_t *r)
{
    static subscriber_t subs[SUBSCRIBERS_MAX];
    memset(r, 0, sizeof(*r));
    r->clients = clients < SUBSCRIBERS_MAX ? clients : SUBSCRIBERS_MAX;
    r->seconds = seconds;
    server_t srv;
    if (!server_start_wsgsim(&srv, wsgsim, log_path, true) || srv.ctl_port == 0) {
        die("%s did not start with a control channel (see %s)", wsgsim, log_path);
    }
    int ctl = tcp_connect(srv.ctl_port);
    for (int i = 0; i < r->clients; i++) {
        subscribe(&subs[i], srv.tcp_port);
    }
    free(control(ctl, "RESUME()\n"));
    read_until(subs, r->clients, now_us() + SETTLE_US, false, r);
    long switches0 = proc_wakeups(srv.pid);
    double t0 = now_us();
    read_until(subs, r->clients, t0 + seconds * 1e6, true, r);
    r->wakeups_per_s = (double)(proc_wakeups(srv.pid) - switches0) / ((now_us() - t0) / 1e6);
    char *state = control(ctl, "STATE?\n");
    r->server_missed = sum_missed(state);
    free(state);
    for (int i = 0; i < r->clients; i++) {
        r->clients_ok += subs[i].values > 0;
        close(subs[i].conn.fd);
    }
    close(ctl);
    server_stop(&srv);
}
