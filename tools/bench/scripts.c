/* SPDX-License-Identifier: BSD-3-Clause */
/* User scripts beside a device (docs/scripting.md, "Limits"): device 0,
 * which runs none, answers SN? and FASTSTOP() beside 1 and beside 32 busy
 * scripts (the scripts share one slice budget per loop pass, so its
 * latency must not grow with them), and FASTSTOP() sent while device 0's
 * own script runs work that cannot pause (a finalizer, pattern
 * backtracking, pcall in a table.sort comparator) is answered once the
 * watchdog has ended it. Device i serves TCP on base port + i. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "bench.h"

#define SN_SAMPLES 2000
#define FASTSTOP_SAMPLES 200
#define FREEZE_RUNS 5 /* of each freeze */
#define START_LIMIT_S 60.0
#define REPLY_MS 60000

static const char *const freezes[] = {
    "setmetatable({}, {__gc = function() while true do end end})\ncollectgarbage()\n",
    "string.find((\"a\"):rep(3000), \".-.-.-.-.-.-b\")\n",
    "table.sort({3, 1, 2}, function(a, b)\n"
    "  while true do pcall(function() local n = 0 while true do n = n + 1 end end) end\n"
    "end)\n",
};
#define FREEZES (sizeof(freezes) / sizeof(freezes[0]))

static void write_file(const char *dir, const char *name, const char *text)
{
    char path[600];
    snprintf(path, sizeof(path), "%s/%s", dir, name);
    FILE *f = fopen(path, "w");
    if (f == NULL || fputs(text, f) < 0 || fclose(f) != 0) {
        die("scripts: cannot write %s", path);
    }
}

/* The store: busy.lua and freeze0.lua ... */
static void make_store(const char *dir)
{
    mkdir(dir, 0755);
    write_file(dir, "busy.lua", "local n = 0\nwhile true do n = n + 1 end\n");
    for (size_t i = 0; i < FREEZES; i++) {
        char name[32];
        snprintf(name, sizeof(name), "freeze%zu.lua", i);
        write_file(dir, name, freezes[i]);
    }
}

static bool start(server_t *srv, const char *wsgsim, const char *out_dir, const char *store,
                  int devices, int base)
{
    char count[16], port[16], log_path[512];
    snprintf(count, sizeof(count), "%d", devices);
    snprintf(port, sizeof(port), "%d", base);
    snprintf(log_path, sizeof(log_path), "%s/wsgsim-scripts.log", out_dir);
    const char *argv[48];
    int n = wsgsim_argv(argv, 40, wsgsim, false);
    for (int i = 0; i < n; i++) { /* device i on base + i */
        if (strcmp(argv[i], "--tcp-port") == 0 || strcmp(argv[i], "--udp-port") == 0) {
            argv[i + 1] = port;
        }
    }
    const char *more[] = {"--devices", count, "--script-dir", store, "--sim-port", "0"};
    for (size_t i = 0; i < sizeof(more) / sizeof(more[0]); i++) {
        argv[n++] = more[i];
    }
    argv[n] = NULL;
    return server_start_cmd(srv, "wsgsim", argv, log_path, START_LIMIT_S);
}

/* One control-channel command, its reply checked. */
static void control(conn_t *ctl, const char *line, const char *expected)
{
    char reply[256];
    if (!conn_send(ctl, line) || !conn_read_line(ctl, reply, sizeof(reply), REPLY_MS) ||
        strncmp(reply, expected, strlen(expected)) != 0) {
        die("scripts: %s: %s", line, reply);
    }
}

static void run_busy(conn_t *ctl, int first, int last)
{
    char line[64];
    for (int i = first; i <= last; i++) {
        snprintf(line, sizeof(line), "DEVICE=%d", i);
        control(ctl, line, line);
        control(ctl, "SCRIPT_RUN(\"busy.lua\")", "ACK SCRIPT_RUN");
    }
}

/* p50 of n round trips of req (FASTSTOP(): each acknowledged after). */
static double p50(conn_t *c, const char *req, int n)
{
    samples_t s;
    samples_init(&s, (size_t)n);
    char reply[128];
    for (int i = 0; i < n; i++) {
        double us;
        if (!rtt_tcp(c, req, &us)) {
            die("scripts: no answer to %s", req);
        }
        samples_add(&s, us);
        if (strcmp(req, "FASTSTOP()") == 0 &&
            (!conn_send(c, "FSACK()") || !conn_read_line(c, reply, sizeof(reply), REPLY_MS))) {
            die("scripts: no answer to FSACK()");
        }
    }
    samples_sort(&s);
    double q = samples_quantile(&s, 0.5);
    samples_free(&s);
    return q;
}

/* The slowest FASTSTOP() answer, sent a millisecond after a freeze's
 * SCRIPT_RUN (so that it arrives while the freeze runs), timed from the
 * SCRIPT_RUN: the freeze's whole length and the answer. */
static double worst_during_freezes(conn_t *ctl, conn_t *gcl)
{
    char line[64], reply[256];
    double worst = 0;
    control(ctl, "DEVICE=0", "DEVICE=0");
    for (int run = 0; run < FREEZE_RUNS; run++) {
        for (size_t i = 0; i < FREEZES; i++) {
            snprintf(line, sizeof(line), "SCRIPT_RUN(\"freeze%zu.lua\")", i);
            double t0 = now_us();
            if (!conn_send(ctl, line) || usleep(1000) != 0 || !conn_send(gcl, "FASTSTOP()") ||
                !conn_read_line(gcl, reply, sizeof(reply), REPLY_MS)) {
                die("scripts: no FASTSTOP() answer during %s", line);
            }
            double ms = (now_us() - t0) / 1000.0;
            worst = ms > worst ? ms : worst;
            if (!conn_read_line(ctl, reply, sizeof(reply), REPLY_MS) ||
                !conn_send(gcl, "FSACK()") ||
                !conn_read_line(gcl, reply, sizeof(reply), REPLY_MS)) {
                die("scripts: %s did not end", line);
            }
        }
    }
    return worst;
}

void scripts_run(const char *wsgsim, const char *out_dir, int busy, scripts_result_t *r)
{
    memset(r, 0, sizeof(*r));
    char store[512];
    snprintf(store, sizeof(store), "%s/scripts-store", out_dir);
    make_store(store);
    int base = free_port_range(busy + 1);
    server_t srv;
    if (!start(&srv, wsgsim, out_dir, store, busy + 1, base) || srv.ctl_port == 0) {
        die("%s --devices %d --script-dir did not start", wsgsim, busy + 1);
    }
    conn_t ctl = {.fd = tcp_connect(srv.ctl_port)};
    conn_t gcl = {.fd = tcp_connect(base)};
    r->busy = busy;
    run_busy(&ctl, 1, 1);
    r->sn_p50_us[0] = p50(&gcl, "SN?", SN_SAMPLES);
    r->faststop_p50_us[0] = p50(&gcl, "FASTSTOP()", FASTSTOP_SAMPLES);
    run_busy(&ctl, 2, busy);
    r->sn_p50_us[1] = p50(&gcl, "SN?", SN_SAMPLES);
    r->faststop_p50_us[1] = p50(&gcl, "FASTSTOP()", FASTSTOP_SAMPLES);
    r->freeze_faststop_ms = worst_during_freezes(&ctl, &gcl);
    close(gcl.fd);
    close(ctl.fd);
    server_stop(&srv);
}
