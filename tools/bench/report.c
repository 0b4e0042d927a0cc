/* SPDX-License-Identifier: BSD-3-Clause */
#include "report.h"

#include <stdlib.h>
#include <string.h>

#define ROWS_MAX 80
#define TARGET_NONE (-1)

typedef struct {
    char name[64];
    const char *unit;
    double wsg;
    double base; /* < 0: no baseline */
    char target[24];
    int met;          /* TARGET_NONE, 0 or 1 */
    const char *note; /* instead of a value: why there is none (never a pass) */
} row_t;

typedef struct {
    row_t row[ROWS_MAX];
    int n;
} table_t;

static row_t *add(table_t *t, const char *name, const char *unit, double wsg, double base)
{
    row_t *r = &t->row[t->n++];
    snprintf(r->name, sizeof(r->name), "%s", name);
    r->unit = unit;
    r->wsg = wsg;
    r->base = base;
    r->target[0] = '\0';
    r->met = TARGET_NONE;
    r->note = NULL;
    return r;
}

/* A target that could not be measured: reported, and not met. */
static void add_missing(table_t *t, const char *name, const char *target_text, const char *why)
{
    row_t *r = add(t, name, "", 0.0, -1.0);
    snprintf(r->target, sizeof(r->target), "%s", target_text);
    r->met = 0;
    r->note = why;
}

static void target(row_t *r, const char *text, int met)
{
    snprintf(r->target, sizeof(r->target), "%s", text);
    r->met = met;
}

static double ratio(const row_t *r)
{
    return r->base > 0 ? r->wsg / r->base : -1.0;
}

static void add_rtt(table_t *t, const char *proto, const samples_t s[2], bool targets)
{
    static const double q[3] = {0.50, 0.99, 0.999};
    static const char *qn[3] = {"p50", "p99", "p99.9"};
    for (int i = 0; i < 3; i++) {
        char name[64];
        snprintf(name, sizeof(name), "%s round trip POS? %s", proto, qn[i]);
        row_t *r = add(t, name, "us", samples_quantile(&s[0], q[i]), samples_quantile(&s[1], q[i]));
        if (targets && i == 0) {
            target(r, "<= 1.3x", ratio(r) <= 1.3);
        } else if (targets && i == 1) {
            target(r, "<= 2x", ratio(r) <= 2.0);
        }
    }
}

static void add_load(table_t *t, const results_t *res)
{
    for (int i = 0; i < LOAD_STEPS; i++) {
        char name[64];
        snprintf(name, sizeof(name), "pipelined throughput, %d client%s", res->load_clients[i],
                 res->load_clients[i] == 1 ? "" : "s");
        row_t *r = add(t, name, "replies/s", res->load_rps[i][0], res->load_rps[i][1]);
        if (res->load_clients[i] == 16) {
            target(r, ">= 0.7x", ratio(r) >= 0.7);
        }
    }
}

static void add_autosend(table_t *t, const results_t *res)
{
    const autosend_result_t *a = res->autosend;
    add(t, "AUTOSEND 16x10 ms period error p50", "us", samples_quantile(&a[0].error_us, 0.5),
        samples_quantile(&a[1].error_us, 0.5));
    row_t *r = add(t, "AUTOSEND 16x10 ms period error p99", "us",
                   samples_quantile(&a[0].error_us, 0.99), samples_quantile(&a[1].error_us, 0.99));
    target(r, "<= 500 us", r->wsg <= 500.0);
    add(t, "AUTOSEND 16x10 ms period error max", "us", samples_max(&a[0].error_us),
        samples_max(&a[1].error_us));
    r = add(t, "AUTOSEND missed periods", "periods", (double)a[0].missed, (double)a[1].missed);
    target(r, "0", a[0].missed == 0 && a[0].clients_ok == res->autosend_clients);
    add(t, "AUTOSEND intervals measured", "lines", (double)a[0].lines, (double)a[1].lines);
}

static double per_second(long count, double seconds)
{
    return seconds > 0 ? (double)count / seconds : 0.0;
}

/* Idle: no wake-up at all; one stray per window is tolerated. */
static void add_idle(table_t *t, const results_t *res)
{
    if (res->idle_s <= 0) {
        return;
    }
    char name[64];
    double s = res->idle_s;
    row_t *r = add(t, "idle wakeups, no clients", "1/s", per_second(res->idle_wakeups[0], s),
                   per_second(res->idle_wakeups[1], s));
    target(r, "0 /s", res->idle_wakeups[0] <= 1);
    r = add(t, "idle CPU, no clients", "% core", res->idle_pct[0], res->idle_pct[1]);
    target(r, "<= 0.05 %", r->wsg <= 0.05);
    snprintf(name, sizeof(name), "idle wakeups, %d idle connections", res->idle_connections);
    r = add(t, name, "1/s", per_second(res->idle_conn_wakeups[0], s),
            per_second(res->idle_conn_wakeups[1], s));
    long more = res->idle_conn_wakeups[0] - res->idle_wakeups[0];
    target(r, "= no clients", more <= 1 || more <= res->idle_wakeups[0] / 20);
    snprintf(name, sizeof(name), "idle CPU, %d idle connections", res->idle_connections);
    r = add(t, name, "% core", res->idle_conn_pct[0], res->idle_conn_pct[1]);
    target(r, "<= 0.05 %", r->wsg <= 0.05);
    add(t, "resident memory after idle", "KiB", (double)res->rss_idle_kib[0],
        (double)res->rss_idle_kib[1]);
}

static void add_memory(table_t *t, const results_t *res)
{
    if (res->rss_peak_kib[0] <= 0) {
        return;
    }
    row_t *r = add(t, "resident memory peak (VmHWM)", "KiB", (double)res->rss_peak_kib[0],
                   (double)res->rss_peak_kib[1]);
    target(r, "<= 8192 KiB", r->wsg > 0 && r->wsg <= 8192.0);
}

/* Callgrind counts: the server's instructions per request. */
static void add_instr(table_t *t, const results_t *res)
{
    const instr_result_t *in = &res->instr;
    if (in->sequential[0] <= 0) {
        return;
    }
    /* The baseline itself: a minimal epoll echo costs 63-103. */
    row_t *r = add(t, "echo baseline: instructions per request", "instr", in->sequential[1], -1.0);
    target(r, "<= 206", r->wsg <= 206.0);
    add(t, "instructions per sequential POS? (paused)", "instr", in->sequential[0],
        in->sequential[1]);
    r = add(t, "instructions per sequential POS? (running)", "instr", in->sequential_running,
            in->sequential[1]);
    target(r, "<= 800", r->wsg <= 800.0);
    r = add(t, "instructions per pipelined POS? line", "instr", in->pipelined[0], in->pipelined[1]);
    target(r, "<= 800", r->wsg <= 800.0);
}

/* The web's JSON written straight into its buffer. */
static void add_web(table_t *t, const results_t *res)
{
    if (res->web.per_state <= 0) {
        return;
    }
    row_t *r =
        add(t, "instructions per GET /api/devices/0/state", "instr", res->web.per_state, -1.0);
    target(r, "<= 60000", r->wsg <= 60000.0);
    r = add(t, "instructions per event-stream event", "instr", res->web.per_event, -1.0);
    target(r, "<= 60000", r->wsg <= 60000.0);
}

/* Scripts share one slice budget per loop pass; the watchdog ends work
 * that cannot pause (docs/scripting.md, "Limits"). */
static void add_scripts(table_t *t, const results_t *res)
{
    const scripts_result_t *s = &res->scripts;
    if (s->busy == 0) {
        return;
    }
    char name[2][48];
    snprintf(name[0], sizeof(name[0]), "SN? p50 beside %d busy scripts (vs 1)", s->busy % 1000);
    snprintf(name[1], sizeof(name[1]), "FASTSTOP() p50 beside %d busy scripts", s->busy % 1000);
    row_t *r = add(t, name[0], "us", s->sn_p50_us[1], s->sn_p50_us[0]);
    target(r, "<= 2x beside 1", ratio(r) <= 2.0);
    add(t, name[1], "us", s->faststop_p50_us[1], s->faststop_p50_us[0]);
    r = add(t, "FASTSTOP() during a script's freeze, slowest", "ms", s->freeze_faststop_ms, -1.0);
    target(r, "<= 50 ms", r->wsg <= 50.0);
}

/* 200 event streams at their rate, GCL's p99 meanwhile. */
static void add_streams(table_t *t, const results_t *res)
{
    const streams_result_t *st = &res->streams;
    if (st->streams == 0) {
        return;
    }
    row_t *r = add(t, "events of the slowest of 200 streams", "events", (double)st->min_events,
                   st->expected_events);
    target(r, ">= 0.9x rate", r->wsg >= 0.9 * st->expected_events);
    add(t, "  median stream there", "events", (double)st->median_events, st->expected_events);
    r = add(t, "TCP round trip POS? p99, 200 streams", "us", st->rtt_p99_us[0], st->rtt_p99_us[1]);
    target(r, "<= 2x echo", ratio(r) <= 2.0);
}

static void add_subscribers(table_t *t, const results_t *res)
{
    const subscribers_result_t *sub = &res->subscribers;
    if (sub->clients == 0) {
        return;
    }
    char name[64];
    snprintf(name, sizeof(name), "AUTOSEND %dx10 ms missed periods (server)", sub->clients);
    row_t *r = add(t, name, "periods", (double)sub->server_missed, -1.0);
    target(r, "0", sub->server_missed == 0 && sub->clients_ok == sub->clients);
    snprintf(name, sizeof(name), "AUTOSEND %dx10 ms wakeups per period", sub->clients);
    r = add(t, name, "wakeups", sub->wakeups_per_s * BENCH_PERIOD_MS / 1000.0, -1.0);
    target(r, "<= 2 (deadlines)", r->wsg <= 2.05);
    snprintf(name, sizeof(name), "AUTOSEND %dx10 ms arrival gaps (client)", sub->clients);
    add(t, name, "periods", (double)sub->client_gaps, -1.0);
    snprintf(name, sizeof(name), "AUTOSEND %dx10 ms values received", sub->clients);
    add(t, name, "lines", (double)sub->lines, -1.0);
}

static void add_fleet(table_t *t, const results_t *res)
{
    const fleet_result_t *f = &res->fleet;
    if (f->devices == 0) {
        return;
    }
    char name[4][64];
    snprintf(name[0], sizeof(name[0]), "fleet: --devices %d start", f->devices);
    snprintf(name[1], sizeof(name[1]), "fleet: --devices %d idle wakeups", f->devices);
    snprintf(name[2], sizeof(name[2]), "fleet: memory per idle device");
    snprintf(name[3], sizeof(name[3]), "fleet: POS? p50, slowest sampled device");
    if (!f->available) {
        static const char why[] = "not available: wsgsim has no --devices option";
        add_missing(t, name[0], "< 1 s", why);
        add_missing(t, name[1], "0 /s", why);
        add_missing(t, name[2], "<= 32 KiB", why);
        add_missing(t, name[3], "<= 1.5x single", why);
        return;
    }
    row_t *r = add(t, name[0], "s", f->start_s, -1.0);
    target(r, "< 1 s", f->start_s < 1.0);
    r = add(t, name[1], "1/s", f->idle_wakeups_per_s, -1.0);
    target(r, "0 /s", f->idle_wakeups_per_s < 0.5);
    r = add(t, name[2], "KiB", f->kib_per_device, -1.0);
    target(r, "<= 32 KiB", f->kib_per_device <= 32.0);
    r = add(t, name[3], "us", f->rtt_p50_us, f->single_rtt_p50_us);
    target(r, "<= 1.5x single", ratio(r) <= 1.5);
}

/* --address-per-device: the start, the peak RSS and
 * the idle wakeups of a cell of N addresses. */
static void add_cell(table_t *t, const results_t *res)
{
    const fleet_cell_result_t *c = &res->cell;
    if (c->devices == 0) {
        return;
    }
    char name[3][64];
    snprintf(name[0], sizeof(name[0]), "cell: %d addresses, start", c->devices);
    snprintf(name[1], sizeof(name[1]), "cell: %d addresses, peak RSS", c->devices);
    snprintf(name[2], sizeof(name[2]), "cell: %d addresses, idle wakeups", c->devices);
    row_t *r = add(t, name[0], "s", c->start_s, -1.0);
    target(r, "< 3 s, SN? ok", c->start_s < 3.0 && c->last_answers);
    r = add(t, name[1], "MiB", (double)c->peak_rss_kib / 1024.0, -1.0);
    target(r, "<= 96 MiB", c->peak_rss_kib <= 96L * 1024L);
    r = add(t, name[2], "1/s", c->idle_wakeups_per_s, -1.0);
    target(r, "0 /s", c->idle_wakeups_per_s < 0.5);
}

static void add_firmware(table_t *t, const results_t *res)
{
    if (!res->firmware_read && res->firmware_expected) {
        add_missing(t, "Cortex-M images within budgets", "within budget",
                    "not measured: run through make bench (--firmware-sizes)");
        return;
    }
    for (int i = 0; i < res->firmware_count; i++) {
        const firmware_size_t *fw = &res->firmware[i];
        char name[64];
        char budget[24];
        snprintf(name, sizeof(name), "%s flash", fw->name);
        row_t *r = add(t, name, "bytes", (double)fw->flash, -1.0);
        snprintf(budget, sizeof(budget), "<= %ld", fw->flash_max);
        target(r, budget, fw->flash <= fw->flash_max);
        snprintf(name, sizeof(name), "%s RAM", fw->name);
        r = add(t, name, "bytes", (double)fw->ram, -1.0);
        snprintf(budget, sizeof(budget), "<= %ld", fw->ram_max);
        target(r, budget, fw->ram <= fw->ram_max);
    }
}

static void add_vtime_ctl(table_t *t, const char *name, const vtime_result_t *c, bool with_target)
{
    double speed = c->wall_s > 0 ? c->virtual_s / c->wall_s : 0.0;
    row_t *r = add(t, name, "x", speed, -1.0);
    if (with_target) {
        target(r, ">= 10000x", speed >= 10000.0 && c->cycles_failed == 0);
    }
    add(t, "  cycles completed / failed there", "cycles", (double)c->cycles_done,
        (double)c->cycles_failed);
}

/* The same client against a responder that simulates nothing: the most
 * any server reaches on this machine, and wsgsim's share of it. */
static void add_vtime_floor(table_t *t, const vtime_result_t *wsgsim, const vtime_result_t *floor)
{
    if (floor->cycles_done == 0 || floor->wall_s <= 0 || wsgsim->wall_s <= 0) {
        return;
    }
    double ceiling = floor->virtual_s / floor->wall_s;
    add(t, "  the same cycles, zero-work responder", "x", ceiling, -1.0);
    add(t, "  wsgsim's share of that ceiling", "%",
        100.0 * (wsgsim->virtual_s / wsgsim->wall_s) / ceiling, -1.0);
}

/* 10,000x in-process, and through wsgsim's paused clock. */
static void add_vtime(table_t *t, const results_t *res)
{
    const vtime_result_t *v = &res->vtime;
    if (v->cycles_done + v->cycles_failed > 0) {
        double speed = v->wall_s > 0 ? v->virtual_s / v->wall_s : 0.0;
        row_t *r = add(t, "virtual time / wall time, in-process", "x", speed, -1.0);
        target(r, ">= 10000x", speed >= 10000.0 && v->cycles_failed == 0);
        add(t, "  cycles completed there", "cycles", (double)v->cycles_done, -1.0);
        add(t, "  virtual time simulated there", "s", v->virtual_s, -1.0);
    }
    /* the target is for one round trip per command once wsgsim has it */
    const vtime_result_t *u = &res->vtime_run_until;
    bool run_until = u->cycles_done + u->cycles_failed > 0;
    const vtime_result_t *c = &res->vtime_ctl;
    if (c->cycles_done + c->cycles_failed > 0) {
        char name[64];
        snprintf(name, sizeof(name), "virtual/wall via wsgsim STEP(%d)", res->vtime_ctl_step_ms);
        add_vtime_ctl(t, name, c, !run_until);
    }
    if (run_until) {
        add_vtime_ctl(t, "virtual/wall via wsgsim RUN_UNTIL_DONE", u, true);
        add_vtime_floor(t, u, &res->vtime_floor);
    }
}

/* The default physics scene: 1x with the clock running on one core, and a
 * paused-clock grip cycle well under a second. */
static void add_physics(table_t *t, const results_t *res)
{
    const physics_result_t *p = &res->physics;
    if (!p->measured) {
        return;
    }
    row_t *r = add(t, "physics: simulated/wall, clock running", "x", p->running_rate, -1.0);
    target(r, ">= 0.95x", p->running_rate >= 0.95);
    r = add(t, "  wsgsim's share of one core there", "%", p->running_cpu_pct, -1.0);
    target(r, "< 100 %", p->running_cpu_pct < 100.0);
    r = add(t, "physics: paused grip cycle, hold 1 s", "s", p->paused_cycle_s, -1.0);
    target(r, "<= 0.5 s", p->paused_cycle_s <= 0.5);
}

/* A scaled clock within 5 % of its rate (the e2e tests no longer time it). */
static void add_scale(table_t *t, const results_t *res)
{
    for (int i = 0; i < SCALE_STEPS; i++) {
        double scale = res->scale.scale[i];
        double rate = res->scale.rate[i];
        if (rate <= 0.0) {
            continue;
        }
        char name[64];
        snprintf(name, sizeof(name), "simulated/wall time at SCALE=%g", scale);
        row_t *r = add(t, name, "x", rate, -1.0);
        target(r, "within 5 %", rate >= 0.95 * scale && rate <= 1.05 * scale);
    }
}

/* The simulated clock keeps wall pace whoever polls the device. */
static void add_pace(table_t *t, const results_t *res)
{
    const pace_result_t *p = &res->pace;
    if (p->quiet_s <= 0.0) {
        return;
    }
    add(t, "MOVE 100 mm at 100 mm/s, quiet device", "s", p->quiet_s, -1.0);
    row_t *r = add(t, "  the same under a POS? flood", "s", p->flooded_s, -1.0);
    target(r, "within 10 % of quiet", p->flooded_s <= 1.1 * p->quiet_s);
    add(t, "  POS? answered meanwhile", "count", (double)p->polls, -1.0);
}

/* A timing profile's waiting is simulated time, not work. */
static void add_timing(table_t *t, const results_t *res)
{
    const timing_result_t *p = &res->timing;
    if (p->requests == 0) {
        return;
    }
    row_t *r = add(t, "1,000 paused POS?, --timing wsg50", "s", p->wsg50_wall_s, -1.0);
    target(r, "< 1 s", p->wsg50_wall_s < 1.0);
    add(t, "  the same under ideal", "s", p->ideal_wall_s, -1.0);
    r = add(t, "wsgsim CPU per request, wsg50", "us", p->wsg50_cpu_us, -1.0);
    target(r, "<= 1.25x ideal", p->wsg50_cpu_us <= 1.25 * p->ideal_cpu_us);
    add(t, "  the same under ideal", "us", p->ideal_cpu_us, -1.0);
}

/* What the recording proxy adds to a round trip, and that it loses nothing. */
static void add_proxy(table_t *t, const results_t *res)
{
    const proxy_result_t *p = &res->proxy;
    if (p->proxied.n == 0) {
        return;
    }
    double p50 = samples_quantile(&p->proxied, 0.50) - samples_quantile(&p->direct, 0.50);
    double p99 = samples_quantile(&p->proxied, 0.99) - samples_quantile(&p->direct, 0.99);
    add(t, "wsgproxy: TCP POS? p50 added", "us", p50, -1.0);
    row_t *r = add(t, "wsgproxy: TCP POS? p99 added", "us", p99, -1.0);
    target(r, "<= 200 us", p99 <= 200.0);
    /* the tails themselves: on a busy machine both are the scheduler's */
    add(t, "  p99 directly to wsgsim", "us", samples_quantile(&p->direct, 0.99), -1.0);
    add(t, "  p99 through the proxy", "us", samples_quantile(&p->proxied, 0.99), -1.0);
    r = add(t, "  pipelined POS? unanswered", "count", (double)(p->pipelined - p->answered), -1.0);
    target(r, "0", p->answered == p->pipelined);
    long missing = 2 * p->expected_in_record - p->recorded_sent - p->recorded_answered;
    r = add(t, "  record lines missing", "count", (double)missing, -1.0);
    target(r, "0", missing == 0);
}

static void build(const results_t *res, table_t *t)
{
    t->n = 0;
    /* work only for what is active */
    add_instr(t, res);
    add_web(t, res);
    add_streams(t, res);
    add_idle(t, res);
    add_subscribers(t, res);
    add_vtime(t, res);
    add_fleet(t, res);
    add_cell(t, res);
    add_scripts(t, res);
    add_firmware(t, res);
    /* against the echo baseline */
    if (res->rtt_tcp[0].n > 0) {
        add_rtt(t, "TCP", res->rtt_tcp, true);
        add_rtt(t, "UDP", res->rtt_udp, false);
        add(t, "UDP datagrams lost", "count", (double)res->udp_lost[0], (double)res->udp_lost[1]);
    }
    if (res->load_clients[0] > 0) {
        add_load(t, res);
    }
    if (res->autosend_clients > 0) {
        add_autosend(t, res);
    }
    add_memory(t, res);
    add_scale(t, res);
    add_physics(t, res);
    add_pace(t, res);
    add_timing(t, res);
    add_proxy(t, res);
}

static const char *met_text(int met)
{
    return met == TARGET_NONE ? "" : met ? "\u2714" : "\u2718";
}

/* Prints text padded to `width` columns (UTF-8 aware). */
static void put_padded(FILE *out, const char *text, int width)
{
    int columns = 0;
    for (const char *c = text; *c != '\0'; c++) {
        columns += ((unsigned char)*c & 0xC0u) != 0x80u;
    }
    fputs(text, out);
    for (; columns < width; columns++) {
        fputc(' ', out);
    }
}

static void format_value(char *out, size_t cap, double v)
{
    int digits = v != 0 && v < 1.0 && v > -1.0 ? 3 : 1;
    snprintf(out, cap, "%.*f", digits, v);
}

void report_print(const results_t *res, FILE *out)
{
    table_t t;
    build(res, &t);
    fprintf(out, "\nwsgsim benchmark on %s (baseline: C line-echo server, same run)\n",
            res->machine);
    fprintf(out, "round trips: %s\n\n", res->placement);
    fprintf(out, "| %-42s | %-9s | %12s | %12s | %8s | %-16s | %s |\n", "metric", "unit", "wsgsim",
            "baseline", "ratio", "target", "ok");
    fprintf(out, "|%.44s|%.11s|%.14s|%.14s|%.10s|%.18s|----|\n",
            "-----------------------------------------------", "-------------", "----------------",
            "----------------", "------------", "-------------------");
    for (int i = 0; i < t.n; i++) {
        const row_t *r = &t.row[i];
        char value[64] = "-";
        char base[32] = "-";
        char rat[32] = "-";
        format_value(value, sizeof(value), r->wsg);
        if (r->base >= 0) {
            format_value(base, sizeof(base), r->base);
        }
        if (ratio(r) >= 0) {
            snprintf(rat, sizeof(rat), "%.2fx", ratio(r));
        }
        fprintf(out, "| %-42s | %-9s | ", r->name, r->unit);
        if (r->note != NULL) {
            fprintf(out, "%-42s | %-16s | %s  |\n", r->note, r->target, met_text(r->met));
            continue;
        }
        fprintf(out, "%12s | %12s | %8s | %-16s | ", value, base, rat, r->target);
        put_padded(out, met_text(r->met), 2);
        fputs(" |\n", out);
    }
    fputc('\n', out);
}

static void json_row(FILE *f, const row_t *r, bool last)
{
    fprintf(f, "    {\"metric\": \"%s\", \"unit\": \"%s\", ", r->name, r->unit);
    if (r->note != NULL) {
        fprintf(f, "\"wsgsim\": null, \"note\": \"%s\", ", r->note);
    } else {
        fprintf(f, "\"wsgsim\": %.3f, ", r->wsg);
    }
    if (r->base >= 0) {
        fprintf(f, "\"baseline\": %.3f, ", r->base);
    } else {
        fprintf(f, "\"baseline\": null, ");
    }
    if (ratio(r) >= 0) {
        fprintf(f, "\"ratio\": %.4f, ", ratio(r));
    } else {
        fprintf(f, "\"ratio\": null, ");
    }
    fprintf(f, "\"target\": \"%s\", \"met\": %s}%s\n", r->target,
            r->met == TARGET_NONE ? "null"
            : r->met              ? "true"
                                  : "false",
            last ? "" : ",");
}

void report_write_json(const results_t *res, const char *dir)
{
    table_t t;
    build(res, &t);
    char path[512];
    snprintf(path, sizeof(path), "%s/results.json", dir);
    FILE *f = fopen(path, "w");
    if (f == NULL) {
        die("cannot write %s", path);
    }
    fprintf(f, "{\n  \"machine\": \"%s\",\n  \"baseline\": \"C line-echo server\",\n",
            res->machine);
    fprintf(f, "  \"round_trip_placement\": \"%s\",\n", res->placement);
    fprintf(f, "  \"rtt_samples\": %zu,\n  \"results\": [\n", res->rtt_tcp[0].n);
    for (int i = 0; i < t.n; i++) {
        json_row(f, &t.row[i], i + 1 == t.n);
    }
    fprintf(f, "  ]\n}\n");
    fclose(f);
    fprintf(stderr, "wsgbench: wrote %s\n", path);
}

static void write_samples(const samples_t *s, const char *dir, const char *name)
{
    char path[512];
    snprintf(path, sizeof(path), "%s/%s", dir, name);
    FILE *f = fopen(path, "w");
    if (f == NULL) {
        die("cannot write %s", path);
    }
    for (size_t i = 0; i < s->n; i++) {
        fprintf(f, "%.3f %.6f\n", s->v[i], (double)(i + 1) / (double)s->n);
    }
    fclose(f);
}

static const char plot_script[] =
    "set terminal pngcairo size 1200,500 font ',10'\n"
    "set output '%s/latency.png'\n"
    "set multiplot layout 1,2 title 'TCP round trip of POS? (%zu samples each): wsgsim vs "
    "loopback echo'\n"
    "set xlabel 'round trip [us]'\nset grid\n"
    "bw = %.3f\nbin(x) = bw * floor(x / bw)\n"
    "set xrange [0:%.1f]\nset ylabel 'fraction of round trips'\nset title 'histogram'\n"
    "plot '%s/rtt_tcp_wsgsim.dat' using (bin($1)):(1.0/%zu) smooth frequency with steps "
    "lw 2 title 'wsgsim', '%s/rtt_tcp_echo.dat' using (bin($1)):(1.0/%zu) smooth frequency "
    "with steps lw 2 title 'echo baseline'\n"
    "set title 'CDF'\nset logscale x\nset xrange [*:*]\nset ylabel 'cumulative fraction'\n"
    "set key bottom right\n"
    "plot '%s/rtt_tcp_wsgsim.dat' using 1:2 with lines lw 2 title 'wsgsim', "
    "'%s/rtt_tcp_echo.dat' using 1:2 with lines lw 2 title 'echo baseline'\n"
    "unset multiplot\n";

void report_plot(const results_t *res, const char *dir)
{
    const samples_t *s = res->rtt_tcp;
    if (s[0].n == 0 || s[1].n == 0) {
        return; /* --only without the round trips */
    }
    write_samples(&s[0], dir, "rtt_tcp_wsgsim.dat");
    write_samples(&s[1], dir, "rtt_tcp_echo.dat");
    if (system("command -v gnuplot >/dev/null 2>&1") != 0) {
        fprintf(stderr, "wsgbench: gnuplot not installed (Debian: gnuplot-nox): no plot\n");
        return;
    }
    double hi = samples_quantile(&s[0], 0.995);
    double hi_echo = samples_quantile(&s[1], 0.995);
    hi = hi > hi_echo ? hi : hi_echo;
    char path[512];
    snprintf(path, sizeof(path), "%s/latency.gp", dir);
    FILE *f = fopen(path, "w");
    if (f == NULL) {
        die("cannot write %s", path);
    }
    fprintf(f, plot_script, dir, s[0].n, hi / 100.0, hi, dir, s[0].n, dir, s[1].n, dir, dir);
    fclose(f);
    char cmd[600];
    snprintf(cmd, sizeof(cmd), "gnuplot %s", path);
    if (system(cmd) == 0) {
        fprintf(stderr, "wsgbench: wrote %s/latency.png\n", dir);
    } else {
        fprintf(stderr, "wsgbench: gnuplot failed on %s\n", path);
    }
}
