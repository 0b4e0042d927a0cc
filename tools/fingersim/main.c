/* SPDX-License-Identifier: BSD-3-Clause */
/* fingersim: one or two simulated finger nodes (WSG-FMF, WSG-DSA, generic)
 * on a SocketCAN interface, the same node code wsgsim runs on its in-process
 * bus. They follow the gripper's STATE broadcast (docs/finger-bus.md). */
#include <errno.h>
#include <getopt.h>
#include <poll.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "can_socketcan.h"
#include "sim/finger_node.h"
#include "version.h"

typedef struct {
    const char *iface;
    const char *fingers;
    finger_node_params_t params;
} fingersim_options_t;

static can_socketcan_t sock;
static finger_node_t nodes[FBUS_SLOTS];
static volatile sig_atomic_t stop;

static void on_signal(int signo)
{
    (void)signo;
    stop = 1;
}

static uint64_t now_us(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (uint64_t)ts.tv_sec * 1000000u + (uint64_t)ts.tv_nsec / 1000u;
}

static void usage(FILE *out)
{
    fprintf(out,
            "Usage: fingersim --can IFACE [OPTION]...\n"
            "Simulated WSG finger nodes on a SocketCAN bus (see docs/finger-bus.md).\n\n"
            "  --can IFACE      CAN interface, e.g. vcan0 (required)\n"
            "  --fingers A[,B]  finger of slot 0 and 1: none, generic, fmf or dsa\n"
            "                   (default fmf,dsa)\n"
            "  --offset N       FMF reading with nothing touching, until TARE (default 0.6 N)\n"
            "  --noise N        FMF noise, standard deviation (default 0.02 N)\n"
            "  --seed N         noise seed (default fixed)\n"
            "  -V, --version    print the version and exit\n"
            "  -h, --help       print this help and exit\n");
}

/* The one style of every wsgsim program's errors: "fingersim: ...". */
static int usage_error(const char *what, const char *value)
{
    fprintf(stderr, "fingersim: %s '%s' (see --help)\n", what, value);
    return 2;
}

static bool parse_float(const char *text, float *out)
{
    char *end = NULL;
    float v = strtof(text, &end);
    if (end == text || *end != '\0' || v != v) {
        return false;
    }
    *out = v;
    return true;
}

/* 0: run, 1: exit ok, 2: usage error */
static int parse_options(int argc, char **argv, fingersim_options_t *o)
{
    static const struct option longopts[] = {
        {"can", required_argument, NULL, 'c'},    {"fingers", required_argument, NULL, 'f'},
        {"offset", required_argument, NULL, 'o'}, {"noise", required_argument, NULL, 'n'},
        {"seed", required_argument, NULL, 's'},   {"help", no_argument, NULL, 'h'},
        {"version", no_argument, NULL, 'V'},      {NULL, 0, NULL, 0},
    };
    memset(o, 0, sizeof(*o));
    o->fingers = "fmf,dsa";
    wsg_finger_node_defaults(&o->params);
    int opt;
    opterr = 0;
    while ((opt = getopt_long(argc, argv, ":hV", longopts, NULL)) != -1) {
        switch (opt) {
        case 'c':
            o->iface = optarg;
            break;
        case 'f':
            o->fingers = optarg;
            break;
        case 'o':
            if (!parse_float(optarg, &o->params.offset_n)) {
                return usage_error("invalid --offset", optarg);
            }
            break;
        case 'n':
            if (!parse_float(optarg, &o->params.noise_n) || o->params.noise_n < 0.0f) {
                return usage_error("invalid --noise", optarg);
            }
            break;
        case 's':
            o->params.seed = (uint32_t)strtoul(optarg, NULL, 0);
            break;
        case 'h':
            usage(stdout);
            return 1;
        case 'V':
            printf("fingersim %s\n", WSGSIM_VERSION);
            return 1;
        case ':':
            fprintf(stderr, "fingersim: option '%s' needs an argument (see --help)\n",
                    argv[optind - 1]);
            return 2;
        default:
            return usage_error("unknown option", argv[optind - 1]);
        }
    }
    if (optind < argc) {
        return usage_error("invalid argument", argv[optind]);
    }
    if (o->iface == NULL) {
        fprintf(stderr, "fingersim: --can IFACE is required (see --help)\n");
        return 2;
    }
    return 0;
}

static bool open_bus(const fingersim_options_t *o, const fbus_type_t *types)
{
    char err[160];
    if (!can_socketcan_open(&sock, o->iface, err, sizeof(err))) {
        fprintf(stderr, "fingersim: %s\n", err);
        return false;
    }
    hal_can_filter_t filters[HAL_CAN_MAX_FILTERS];
    unsigned count = 0;
    for (unsigned i = 0; i < FBUS_SLOTS; i++) {
        finger_node_params_t p = o->params;
        p.seed = o->params.seed != 0u ? o->params.seed + i : 0u;
        wsg_finger_node_init(&nodes[i], types[i], i, &p, can_socketcan_bus(&sock));
        if (types[i] != FBUS_TYPE_NONE) {
            count += wsg_finger_node_filters(&nodes[i], &filters[count]);
        }
    }
    if (count > 0u && !hal_can_set_filters(can_socketcan_bus(&sock), filters, count)) {
        fprintf(stderr, "fingersim: cannot set CAN filters: %s\n", strerror(-sock.last_error));
        return false;
    }
    return true;
}

static uint64_t next_due(void)
{
    uint64_t due = UINT64_MAX;
    for (unsigned i = 0; i < FBUS_SLOTS; i++) {
        uint64_t d = wsg_finger_node_next_due_us(&nodes[i]);
        due = d < due ? d : due;
    }
    return due;
}

/* Says when the loop woke far later than its nodes were due: the host held
 * fingersim up, and the nodes skip that time (docs/finger-bus.md). */
static void report_stall(uint64_t due, uint64_t now)
{
    if (due != UINT64_MAX && now > due && now - due > FBUS_STALL_US) {
        fprintf(stderr, "fingersim: held up %llu ms\n", (unsigned long long)((now - due) / 1000u));
    }
}

static void run_once(void)
{
    uint64_t due = next_due();
    uint64_t now = now_us();
    int timeout_ms = -1;
    if (due != UINT64_MAX) {
        timeout_ms = due <= now ? 0 : (int)((due - now + 999u) / 1000u);
    }
    struct pollfd pfd = {can_socketcan_fd(&sock), POLLIN, 0};
    if (poll(&pfd, 1, timeout_ms) < 0 && errno != EINTR) {
        perror("fingersim: poll");
        stop = 1;
        return;
    }
    report_stall(due, now_us());
    hal_can_frame_t frame;
    while (hal_can_recv(can_socketcan_bus(&sock), &frame)) {
        now = now_us();
        for (unsigned i = 0; i < FBUS_SLOTS; i++) {
            wsg_finger_node_receive(&nodes[i], &frame, now);
        }
    }
    now = now_us();
    for (unsigned i = 0; i < FBUS_SLOTS; i++) {
        wsg_finger_node_step(&nodes[i], now);
    }
}

int main(int argc, char **argv)
{
    fingersim_options_t o;
    int parsed = parse_options(argc, argv, &o);
    fbus_type_t types[FBUS_SLOTS];
    if (parsed != 0) {
        return parsed == 1 ? 0 : 2;
    }
    if (!wsg_finger_node_parse_pair(o.fingers, types)) {
        return usage_error("invalid --fingers", o.fingers);
    }
    setvbuf(stderr, NULL, _IOLBF, 0);
    signal(SIGINT, on_signal);
    signal(SIGTERM, on_signal);
    if (!open_bus(&o, types)) {
        return 1;
    }
    fprintf(stderr, "fingersim: fingers %s on %s ready\n", o.fingers, o.iface);
    while (!stop) {
        run_once();
    }
    fprintf(stderr, "fingersim: stopped; sent %u+%u frames, tx errors %u\n", nodes[0].frames_sent,
            nodes[1].frames_sent, sock.tx_errors);
    can_socketcan_close(&sock);
    return 0;
}
