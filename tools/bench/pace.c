/* SPDX-License-Identifier: BSD-3-Clause */
/* The simulated clock keeps wall pace under load: the
 * wall time of a 100 mm MOVE at 100 mm/s (1.1 s of simulated time) on a
 * quiet device and while another client sends POS? back to back. The e2e
 * and Check tests assert the rule in virtual time (a query never postpones
 * a control step: tests/conn/test_runner.c); the wall time is measured here. */
#include <poll.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "bench.h"

#define REPLY_MS 10000

static void expect_line(conn_t *c, const char *cmd, const char *want)
{
    char line[256];
    if (!conn_read_line(c, line, sizeof(line), REPLY_MS) || strcmp(line, want) != 0) {
        die("pace: %s answered '%s', not '%s'", cmd, line, want);
    }
}

/* Sends cmd, expects ACK NAME; returns without waiting for the FIN. */
static void start_motion(conn_t *c, const char *cmd, const char *name)
{
    char ack[64];
    snprintf(ack, sizeof(ack), "ACK %s", name);
    if (!conn_send(c, cmd)) {
        die("pace: cannot send %s", cmd);
    }
    expect_line(c, cmd, ack);
}

static void motion(conn_t *c, const char *cmd, const char *name)
{
    char fin[64];
    snprintf(fin, sizeof(fin), "FIN %s", name);
    start_motion(c, cmd, name);
    expect_line(c, cmd, fin);
}

/* Whether a line is waiting on c (or already buffered). */
static bool line_waiting(const conn_t *c)
{
    struct pollfd p = {.fd = c->fd, .events = POLLIN};
    return memchr(c->buf, '\n', c->len) != NULL || poll(&p, 1, 0) > 0;
}

/* The MOVE's wall time in s; with flood, POS? round trips on it meanwhile. */
static double timed_move(conn_t *c, conn_t *flood, long *polls)
{
    motion(c, "MOVE(0,400)", "MOVE");
    double t0 = now_us();
    start_motion(c, "MOVE(100,100)", "MOVE");
    while (flood != NULL && !line_waiting(c)) {
        char pos[64];
        if (!conn_send(flood, "POS?") || !conn_read_line(flood, pos, sizeof(pos), REPLY_MS)) {
            die("pace: the flooding client got no answer");
        }
        (*polls)++;
    }
    expect_line(c, "MOVE(100,100)", "FIN MOVE");
    return (now_us() - t0) / 1e6;
}

void pace_run(const server_t *srv, pace_result_t *r)
{
    conn_t c = {.fd = tcp_connect(srv->tcp_port)};
    conn_t flood = {.fd = tcp_connect(srv->tcp_port)};
    motion(&c, "HOME()", "HOME");
    r->quiet_s = timed_move(&c, NULL, &r->polls);
    r->flooded_s = timed_move(&c, &flood, &r->polls);
    conn_send(&flood, "BYE()");
    conn_send(&c, "BYE()");
    close(flood.fd);
    close(c.fd);
}
