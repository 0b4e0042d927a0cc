#include "report.h"

#include <stdlib.h>
#include <string.h>

#define ROWS_MAX 32
#define TARGET_NONE (-1)

typedef struct {
    char name[64];
    const char *unit;
    double wsg;
    double base; /* < 0: no baseline */
    const char *target;
    int met; /* TARGET_NONE, 0 or 1 */
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
    r->target = "";
    r->met = TARGET_NONE;
    return r;
}

static void target(row_t *r, const char *text, int met)
{
    r->target = text;
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

static void add_idle(table_t *t, const results_t *res)
{
    row_t *r = add(t, "idle CPU, no clients", "% core", res->idle_pct[0], res->idle_pct[1]);
    target(r, "<= 0.5 %", r->wsg <= 0.5);
    r = add(t, "idle CPU, 8 idle connections", "% core", res->idle_conn_pct[0],
            res->idle_conn_pct[1]);
    target(r, "<= 0.5 %", r->wsg <= 0.5);
    add(t, "context switches while idle, no clients", "count", (double)res->idle_wakeups[0],
        (double)res->idle_wakeups[1]);
    add(t, "resident memory after idle", "KiB", (double)res->rss_idle_kib[0],
        (double)res->rss_idle_kib[1]);
    r = add(t, "resident memory peak (VmHWM)", "KiB", (double)res->rss_peak_kib[0],
            (double)res->rss_peak_kib[1]);
    target(r, "<= 8192 KiB", r->wsg > 0 && r->wsg <= 8192.0);
}

static void add_vtime(table_t *t, const results_t *res)
{
    const vtime_result_t *v = &res->vtime;
    double speed = v->wall_s > 0 ? v->virtual_s / v->wall_s : 0.0;
    row_t *r = add(t, "virtual time / wall time", "x", speed, 1.0);
    target(r, ">= 1000x", speed >= 1000.0 && v->cycles_failed == 0);
    add(t, "virtual-time cycles completed", "cycles", (double)v->cycles_done, -1.0);
    add(t, "virtual time simulated", "s", v->virtual_s, -1.0);
    const vtime_result_t *c = &res->vtime_ctl;
    if (c->cycles_done + c->cycles_failed > 0) {
        char name[64];
        snprintf(name, sizeof(name), "virtual/wall via wsgsim STEP(%d)", res->vtime_ctl_step_ms);
        r = add(t, name, "x", c->wall_s > 0 ? c->virtual_s / c->wall_s : 0.0, 1.0);
        add(t, "  cycles completed / failed there", "cycles", (double)c->cycles_done,
            (double)c->cycles_failed);
    }
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

static void build(const results_t *res, table_t *t)
{
    t->n = 0;
    add_rtt(t, "TCP", res->rtt_tcp, true);
    add_rtt(t, "UDP", res->rtt_udp, false);
    add(t, "UDP datagrams lost", "count", (double)res->udp_lost[0], (double)res->udp_lost[1]);
    add_load(t, res);
    add_autosend(t, res);
    add_idle(t, res);
    add_vtime(t, res);
    add_scale(t, res);
}

static const char *met_text(int met)
{
    return met == TARGET_NONE ? "" : met ? "met" : "NOT MET";
}

void report_print(const results_t *res, FILE *out)
{
    table_t t;
    build(res, &t);
    fprintf(out, "\nwsgsim benchmark on %s (baseline: C line-echo server, same run)\n",
            res->machine);
    fprintf(out, "round trips: %s\n\n", res->placement);
    fprintf(out, "| %-40s | %-9s | %12s | %12s | %8s | %-11s | %-7s |\n", "metric", "unit",
            "wsgsim", "baseline", "ratio", "target", "result");
    fprintf(out, "|%.42s|%.11s|%.14s|%.14s|%.10s|%.13s|%.9s|\n",
            "-----------------------------------------------", "-------------", "----------------",
            "----------------", "------------", "---------------", "-----------");
    for (int i = 0; i < t.n; i++) {
        const row_t *r = &t.row[i];
        char base[32] = "-";
        char rat[32] = "-";
        if (r->base >= 0) {
            snprintf(base, sizeof(base), "%.*f", r->base != 0 && r->base < 1.0 ? 3 : 1, r->base);
        }
        if (ratio(r) >= 0) {
            snprintf(rat, sizeof(rat), "%.2fx", ratio(r));
        }
        int digits = r->wsg != 0 && r->wsg < 1.0 && r->wsg > -1.0 ? 3 : 1;
        fprintf(out, "| %-40s | %-9s | %12.*f | %12s | %8s | %-11s | %-7s |\n", r->name, r->unit,
                digits, r->wsg, base, rat, r->target, met_text(r->met));
    }
    fputc('\n', out);
}

static void json_row(FILE *f, const row_t *r, bool last)
{
    fprintf(f, "    {\"metric\": \"%s\", \"unit\": \"%s\", \"wsgsim\": %.3f, ", r->name, r->unit,
            r->wsg);
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
