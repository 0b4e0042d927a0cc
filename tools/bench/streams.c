/* SPDX-License-Identifier: BSD-3-Clause */
/* Event-stream clients: STREAM_ADDRESSES client addresses
 * (127.0.0.20 and up) open STREAMS_PER_ADDRESS streams each on
 * /api/devices/0/events of a free-running wsgsim, and a child process
 * counts every stream's events for a window; meanwhile this process times
 * GCL POS? round trips against that wsgsim and against the echo baseline,
 * in alternating blocks, so that both see the streams' load alike. */
#include <arpa/inet.h>
#include <errno.h>
#include <netinet/in.h>
#include <poll.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include "bench.h"

#define STREAM_ADDRESSES 20
#define STREAMS_PER_ADDRESS 10
#define STREAMS (STREAM_ADDRESSES * STREAMS_PER_ADDRESS)
#define RTT_BLOCKS 10
#define CONNECT_TIMEOUT_US 60e6

static const char events_request[] =
    "GET /api/devices/0/events HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n";

/* A stream from 127.0.0.(20 + address): connected and asked for events. */
static int open_stream(int port, int address)
{
    int fd = socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
    struct sockaddr_in from = {.sin_family = AF_INET};
    from.sin_addr.s_addr = htonl(INADDR_LOOPBACK + 20u + (unsigned)address);
    struct sockaddr_in to = {.sin_family = AF_INET, .sin_port = htons((uint16_t)port)};
    to.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    double deadline = now_us() + CONNECT_TIMEOUT_US;
    while (fd >= 0 && bind(fd, (struct sockaddr *)&from, sizeof(from)) == 0 &&
           connect(fd, (struct sockaddr *)&to, sizeof(to)) != 0) {
        if (now_us() > deadline) {
            die("streams: cannot connect to the web port %d: %s", port, strerror(errno));
        }
        close(fd); /* the web server is not up yet */
        usleep(20000);
        fd = socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
    }
    if (fd < 0 || send(fd, events_request, sizeof(events_request) - 1, MSG_NOSIGNAL) < 0) {
        die("streams: cannot open a stream: %s", strerror(errno));
    }
    return fd;
}

/* Events end with a blank line ("\n\n"); the HTTP header ends "\r\n\r\n". */
static long count_ends(const char *buf, ssize_t n, char *last)
{
    long ends = 0;
    for (ssize_t i = 0; i < n; i++) {
        ends += buf[i] == '\n' && *last == '\n';
        *last = buf[i];
    }
    return ends;
}

/* In the child: every stream's events over `seconds` after the first event
 * of the last stream, written to `out` as STREAMS longs. Tells `ready`
 * once every stream has had its first event. */
static void read_streams(int port, double seconds, int ready, int out)
{
    static struct pollfd fds[STREAMS];
    static long events[STREAMS];
    static char last[STREAMS];
    for (int i = 0; i < STREAMS; i++) {
        fds[i] =
            (struct pollfd){.fd = open_stream(port, i / STREAMS_PER_ADDRESS), .events = POLLIN};
    }
    char buf[65536];
    int started = 0;
    double end = 0;
    double start_deadline = now_us() + CONNECT_TIMEOUT_US;
    while (started < STREAMS || now_us() < end) {
        if (started < STREAMS && now_us() > start_deadline) {
            die("streams: %d of %d streams had an event within %.0f s", started, STREAMS,
                CONNECT_TIMEOUT_US / 1e6);
        }
        if (poll(fds, STREAMS, 1000) < 0 && errno != EINTR) {
            die("streams: poll failed");
        }
        for (int i = 0; i < STREAMS; i++) {
            ssize_t n = (fds[i].revents & (POLLIN | POLLHUP)) != 0
                            ? recv(fds[i].fd, buf, sizeof(buf), 0)
                            : -1;
            long ends = n > 0 ? count_ends(buf, n, &last[i]) : 0;
            if (ends > 0 && events[i] == 0 && ++started == STREAMS) {
                memset(events, 0, sizeof(events)); /* the window opens now */
                end = now_us() + seconds * 1e6;
                (void)!write(ready, "r", 1);
                ends = 0;
            }
            events[i] += started == STREAMS ? ends : (ends > 0);
        }
    }
    (void)!write(out, events, sizeof(events));
    _exit(0);
}

static void rtt_block(conn_t *c, int n, samples_t *out)
{
    for (int i = 0; i < n; i++) {
        double us;
        if (!rtt_tcp(c, "POS?", &us)) {
            die("streams: no reply to POS?");
        }
        samples_add(out, us);
    }
}

static int compare_longs(const void *a, const void *b)
{
    long x = *(const long *)a, y = *(const long *)b;
    return (x > y) - (x < y);
}

void streams_run(const char *wsgsim, const char *out_dir, double seconds, int rtt_n,
                 const char *pin, streams_result_t *r)
{
    fprintf(stderr, "wsgbench: %d event streams from %d addresses (%.0f s)\n", STREAMS,
            STREAM_ADDRESSES, seconds);
    char log_path[512], port_text[16];
    snprintf(log_path, sizeof(log_path), "%s/wsgsim-streams.log", out_dir);
    int http_port = free_port_range(1);
    snprintf(port_text, sizeof(port_text), "%d", http_port);
    const char *argv[64];
    int n = wsgsim_argv(argv, 60, wsgsim, false);
    argv[n++] = "--http-port";
    argv[n++] = port_text;
    argv[n] = NULL;
    server_t srv[2];
    if (!server_start_cmd(&srv[0], "wsgsim", argv, log_path, 30.0) || !server_start_echo(&srv[1])) {
        die("streams: a server did not start (see %s)", log_path);
    }
    int ready[2], counts[2];
    if (pipe(ready) != 0 || pipe(counts) != 0) {
        die("streams: pipe failed");
    }
    pid_t child = fork();
    if (child == 0) {
        read_streams(http_port, seconds, ready[1], counts[1]);
    }
    char byte;
    if (read(ready[0], &byte, 1) != 1) {
        die("streams: the streams did not all start");
    }
    /* the reader stands in for browsers on other machines: it is kept off
     * the CPU of the servers and their timed client (--pin) */
    place_apart(child, pin);
    server_t *servers[2] = {&srv[0], &srv[1]};
    char placement[96];
    place_round_trips(servers, 2, pin, placement, sizeof(placement));
    conn_t c[2] = {{.fd = tcp_connect(srv[0].tcp_port)}, {.fd = tcp_connect(srv[1].tcp_port)}};
    samples_t rtt[2];
    for (int k = 0; k < 2; k++) {
        samples_init(&rtt[k], (size_t)rtt_n);
    }
    for (int b = 0; b < RTT_BLOCKS; b++) {
        for (int k = 0; k < 2; k++) {
            rtt_block(&c[k], rtt_n / RTT_BLOCKS, &rtt[k]);
        }
    }
    unplace_round_trips(servers, 2);
    long events[STREAMS];
    if (read(counts[0], events, sizeof(events)) != (ssize_t)sizeof(events)) {
        die("streams: the reader reported no counts");
    }
    waitpid(child, NULL, 0);
    qsort(events, STREAMS, sizeof(events[0]), compare_longs);
    r->streams = STREAMS;
    r->expected_events = seconds * 1000.0 / WEB_EVENTS_PERIOD_MS_BENCH;
    r->min_events = events[0];
    r->median_events = events[STREAMS / 2];
    for (int k = 0; k < 2; k++) {
        samples_sort(&rtt[k]);
        r->rtt_p99_us[k] = samples_quantile(&rtt[k], 0.99);
        samples_free(&rtt[k]);
        close(c[k].fd);
        server_stop(&srv[k]);
    }
}
