/* SPDX-License-Identifier: BSD-3-Clause */
/* Results of one benchmark run: the table, results.json and the plot. */
#ifndef BENCH_REPORT_H
#define BENCH_REPORT_H

#include <stdio.h>

#include "bench.h"

#define LOAD_STEPS 4

#define FIRMWARE_IMAGES_MAX 4

/* One Cortex-M image against its budgets (bytes), from `make bench`. */
typedef struct {
    char name[32];
    long flash, flash_max;
    long ram, ram_max;
} firmware_size_t;

/* Index 0: wsgsim, 1: echo baseline. */
typedef struct {
    char machine[256];
    char placement[96]; /* CPU placement of the round trips */
    double idle_s;      /* each idle window; 0: not run */
    int idle_connections;
    double idle_pct[2];
    long idle_wakeups[2]; /* sleeps (voluntary context switches) in the window */
    double idle_conn_pct[2];
    long idle_conn_wakeups[2];
    long rss_idle_kib[2];
    long rss_peak_kib[2];
    samples_t rtt_tcp[2];
    samples_t rtt_udp[2];
    long udp_lost[2];
    int load_clients[LOAD_STEPS];
    double load_rps[LOAD_STEPS][2];
    autosend_result_t autosend[2];
    int autosend_clients;
    vtime_result_t vtime;
    vtime_result_t vtime_ctl; /* through wsgsim's control channel; 0 cycles: not run */
    int vtime_ctl_step_ms;
    vtime_result_t vtime_run_until; /* the same with RUN_UNTIL_DONE; 0 cycles: not run */
    vtime_result_t vtime_floor;     /* the same against the zero-work responder */
    instr_result_t instr;
    web_result_t web;
    streams_result_t streams;
    subscribers_result_t subscribers;
    fleet_result_t fleet;
    fleet_cell_result_t cell;
    scripts_result_t scripts;
    bool firmware_expected; /* a full run: the sizes belong in it */
    bool firmware_read;     /* --firmware-sizes given */
    int firmware_count;
    firmware_size_t firmware[FIRMWARE_IMAGES_MAX];
    scale_result_t scale;     /* the scaled clock's rate; rate 0: not run */
    pace_result_t pace;       /* a MOVE's wall time under a POS? flood */
    timing_result_t timing;   /* requests under a timing profile */
    proxy_result_t proxy;     /* what the recording proxy adds */
    physics_result_t physics; /* the default physics scene */
} results_t;

void report_print(const results_t *res, FILE *out);
void report_write_json(const results_t *res, const char *dir);
/* PNG latency histogram and CDF with gnuplot, if it is installed. */
void report_plot(const results_t *res, const char *dir);

#endif
