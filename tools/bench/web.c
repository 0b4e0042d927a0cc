/* SPDX-License-Identifier: BSD-3-Clause */
/* The web interface's cost, counted by callgrind as instr.c counts POS?: a
 * wsgsim with its clock paused and the default fingers (an FMF and a DSA,
 * whose 84 cells make the largest state) runs under callgrind; the state
 * is the one users see: the fingers up and sending their data, the part
 * held (vtime_hold_part()). Then one client sends GET
 * /api/devices/0/state on one keep-alive connection, one request at a
 * time, then reads events from /api/devices/0/events. Runs that differ
 * only in the number of requests or events give the cost of one as a
 * difference. An event includes the wake-up of its tick. */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <unistd.h>

#include "bench.h"

#define STATE_BASE 20
#define EVENT_BASE 10
#define WEB_START_S 120.0
#define WEB_STOP_S 120.0
#define RESPONSE_MAX 65536

static const char state_request[] = "GET /api/devices/0/state HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n";
static const char events_request[] =
    "GET /api/devices/0/events HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n";

/* The web port accepts once the server is up; callgrind makes that slow. */
static int connect_web(int port)
{
    double deadline = now_us() + WEB_START_S * 1e6;
    while (now_us() < deadline) {
        int fd = try_tcp_connect(port);
        if (fd >= 0) {
            return fd;
        }
        usleep(20000);
    }
    die("web: nothing accepts on port %d", port);
}

static size_t read_more(int fd, char *buf, size_t len, const char *what)
{
    ssize_t n = recv(fd, buf + len, RESPONSE_MAX - 1 - len, 0);
    if (n <= 0) {
        die("web under callgrind: connection ended while reading %s", what);
    }
    buf[len + (size_t)n] = '\0';
    return len + (size_t)n;
}

/* One GET and its whole response (headers and Content-Length bytes). */
static void get_state(int fd)
{
    if (send(fd, state_request, sizeof(state_request) - 1, MSG_NOSIGNAL) < 0) {
        die("web: send failed: %s", strerror(errno));
    }
    static char buf[RESPONSE_MAX];
    size_t len = 0;
    const char *body;
    while ((body = strstr(buf, "\r\n\r\n")) == NULL || len == 0) {
        len = read_more(fd, buf, len, "a state");
    }
    const char *length = strcasestr(buf, "content-length:");
    if (length == NULL || strncmp(buf, "HTTP/1.1 200", 12) != 0) {
        die("web: unexpected state response: %.80s", buf);
    }
    size_t want = (size_t)(body + 4 - buf) + strtoul(length + 15, NULL, 10);
    while (len < want) {
        len = read_more(fd, buf, len, "a state");
    }
    buf[0] = '\0';
}

/* Reads until `count` events ("\n\n" ends each) have come. */
static void read_events(int fd, int count)
{
    static char buf[RESPONSE_MAX];
    size_t len = 0;
    int seen = 0;
    while (seen < count) {
        len = read_more(fd, buf, len, "events");
        char *end;
        while ((end = strstr(buf, "\n\n")) != NULL) {
            seen += strncmp(buf, "HTTP/", 5) != 0 && strstr(buf, "event: state") != NULL;
            size_t used = (size_t)(end + 2 - buf);
            memmove(buf, end + 2, len - used + 1);
            len -= used;
        }
    }
}

static double counted_run(const char *wsgsim, const char *out_dir, int states, int events)
{
    char out_opt[600], out_path[512], log_path[512], port_text[16];
    snprintf(out_path, sizeof(out_path), "%s/callgrind.web.%d.%d.out", out_dir, states, events);
    snprintf(out_opt, sizeof(out_opt), "--callgrind-out-file=%s", out_path);
    snprintf(log_path, sizeof(log_path), "%s/callgrind.web.log", out_dir);
    int port = free_port_range(1);
    snprintf(port_text, sizeof(port_text), "%d", port);
    const char *argv[64] = {"valgrind", "--tool=callgrind", out_opt};
    int n = 3 + wsgsim_argv(argv + 3, 56, wsgsim, true);
    argv[n++] = "--http-port";
    argv[n++] = port_text;
    argv[n] = NULL;
    unlink(out_path);
    server_t srv;
    if (!server_start_cmd(&srv, "wsgsim", argv, log_path, WEB_START_S)) {
        die("wsgsim did not start under callgrind with the web on (see %s)", log_path);
    }
    vtime_hold_part(&srv);
    int fd = connect_web(port);
    for (int i = 0; i < states; i++) {
        get_state(fd);
    }
    close(fd);
    fd = connect_web(port);
    if (send(fd, events_request, sizeof(events_request) - 1, MSG_NOSIGNAL) < 0) {
        die("web: send failed: %s", strerror(errno));
    }
    read_events(fd, events);
    if (!server_stop_within(&srv, WEB_STOP_S)) {
        die("wsgsim under callgrind did not exit on SIGTERM (see %s)", log_path);
    }
    close(fd);
    return callgrind_total(out_path);
}

void web_run(const char *wsgsim, const char *out_dir, int state_n, int event_n, web_result_t *r)
{
    fprintf(stderr, "wsgbench: callgrind, web: base, +%d GET state, +%d events\n", state_n,
            event_n);
    double base = counted_run(wsgsim, out_dir, STATE_BASE, EVENT_BASE);
    double states = counted_run(wsgsim, out_dir, STATE_BASE + state_n, EVENT_BASE);
    double events = counted_run(wsgsim, out_dir, STATE_BASE, EVENT_BASE + event_n);
    r->per_state = (states - base) / state_n;
    r->per_event = (events - base) / event_n;
}
