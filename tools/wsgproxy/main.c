/* SPDX-License-Identifier: BSD-3-Clause */
/* wsgproxy: see proxy.h and docs/calibration.md. */
#include <arpa/inet.h>
#include <errno.h>
#include <getopt.h>
#include <netdb.h>
#include <netinet/in.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "log.h"
#include "proxy.h"
#include "record_file.h"
#include "version.h"

static proxy_t proxy; /* one per process: its peers table is large */

uint64_t proxy_now_us(const proxy_t *p)
{
    return (loop_monotonic_ns() - p->start_ns) / 1000u;
}

typedef struct {
    proxy_t *p;
    const char *channel;
    char direction;
    uint64_t at_us;
} unit_target_t;

/* A line is in stdio's buffer: written out within PROXY_FLUSH_NS. */
static void mark_dirty(proxy_t *p)
{
    if (!p->record_dirty) {
        p->record_dirty = true;
        p->flush_ns = loop_monotonic_ns() + PROXY_FLUSH_NS;
    }
}

static void put_unit(void *ctx, const unsigned char *unit, size_t len)
{
    const unit_target_t *t = ctx;
    record_file_put(t->p->record, t->at_us, t->channel, t->direction, (const char *)unit, len);
    mark_dirty(t->p);
}

void proxy_record(proxy_t *p, splitter_t *split, const char *channel, char direction,
                  const unsigned char *data, size_t len, uint64_t at_us, bool flush)
{
    if (p->record == NULL) {
        return;
    }
    unit_target_t target = {p, channel, direction, at_us};
    if (len > 0u) {
        split_feed(split, data, len, put_unit, &target);
    }
    if (flush) {
        split_flush(split, put_unit, &target);
        split->kind = SPLIT_UNDECIDED;
    }
}

void proxy_log(const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    fputs("wsgproxy: ", stderr);
    vfprintf(stderr, fmt, ap);
    va_end(ap);
    fputc('\n', stderr);
}

void proxy_note(proxy_t *p, const char *fmt, ...)
{
    if (p->record == NULL) {
        return;
    }
    uint64_t now = proxy_now_us(p);
    fprintf(p->record, "# %llu.%06llu ", (unsigned long long)(now / 1000000u),
            (unsigned long long)(now % 1000000u));
    va_list ap;
    va_start(ap, fmt);
    vfprintf(p->record, fmt, ap);
    va_end(ap);
    fputc('\n', p->record);
    mark_dirty(p);
}

void proxy_set_port(struct sockaddr_storage *ss, int port)
{
    if (ss->ss_family == AF_INET) {
        ((struct sockaddr_in *)ss)->sin_port = htons((uint16_t)port);
    } else {
        ((struct sockaddr_in6 *)ss)->sin6_port = htons((uint16_t)port);
    }
}

struct sockaddr_storage proxy_gripper_at(const proxy_t *p, int port)
{
    struct sockaddr_storage to = p->gripper;
    proxy_set_port(&to, port);
    return to;
}

static const char usage[] =
    "Usage: wsgproxy --gripper HOST [OPTION]...\n"
    "A transparent recording proxy between a WSG driver and a gripper: point the\n"
    "driver at the proxy, the proxy at the gripper. Every GCL line and binary\n"
    "frame both ways is passed on unchanged and written to the record with its\n"
    "time (wsgsim's record format, read by wsgplot).\n"
    "\n"
    "  --gripper HOST                 the gripper's address (required)\n"
    "  --record FILE                  write the record to FILE (truncated)\n"
    "  --listen ADDR                  the proxy's address for the driver (default\n"
    "                                 0.0.0.0)\n"
    "  --tcp-port N                   GCL and binary over TCP (default 1000; 0: a\n"
    "                                 free port)\n"
    "  --udp-port N|off               GCL over UDP (default: the TCP port)\n"
    "  --binary-udp-port N|off        binary over UDP (default 1500)\n"
    "  --binary-udp-reply-port N      the driver's port binary UDP replies go to\n"
    "                                 (default 1501; 0: the port it sent from)\n"
    "  --gripper-tcp-port N           the gripper's TCP port (default 1000)\n"
    "  --gripper-udp-port N           its GCL UDP port (default: its TCP port)\n"
    "  --gripper-binary-udp-port N    its binary UDP port (default 1500)\n"
    "  --gripper-binary-reply-port N  the proxy's port the gripper sends binary UDP\n"
    "                                 replies to (default 1501; 0: the port the\n"
    "                                 request came from)\n"
    "  --ready-file FILE              once serving, write pid and ports to FILE\n"
    "  -h, --help                     this help\n"
    "  -V, --version                  the version\n"
    "\n"
    "On the driver's machine the ports 1500 and 1501 are the driver's: run the\n"
    "proxy on another address or machine for binary UDP (docs/calibration.md).\n"
    "Exit status: 0 after SIGINT or SIGTERM, 2 for a bad argument or a port that\n"
    "cannot be opened.\n";

enum {
    OPT_GRIPPER = 256,
    OPT_RECORD,
    OPT_LISTEN,
    OPT_TCP,
    OPT_UDP,
    OPT_BIN,
    OPT_BIN_REPLY,
    OPT_G_TCP,
    OPT_G_UDP,
    OPT_G_BIN,
    OPT_G_BIN_REPLY,
    OPT_READY,
    OPT_HELP,
    OPT_VERSION
};

static const struct option long_options[] = {
    {"gripper", required_argument, NULL, OPT_GRIPPER},
    {"record", required_argument, NULL, OPT_RECORD},
    {"listen", required_argument, NULL, OPT_LISTEN},
    {"tcp-port", required_argument, NULL, OPT_TCP},
    {"udp-port", required_argument, NULL, OPT_UDP},
    {"binary-udp-port", required_argument, NULL, OPT_BIN},
    {"binary-udp-reply-port", required_argument, NULL, OPT_BIN_REPLY},
    {"gripper-tcp-port", required_argument, NULL, OPT_G_TCP},
    {"gripper-udp-port", required_argument, NULL, OPT_G_UDP},
    {"gripper-binary-udp-port", required_argument, NULL, OPT_G_BIN},
    {"gripper-binary-reply-port", required_argument, NULL, OPT_G_BIN_REPLY},
    {"ready-file", required_argument, NULL, OPT_READY},
    {"help", no_argument, NULL, OPT_HELP},
    {"version", no_argument, NULL, OPT_VERSION},
    {NULL, 0, NULL, 0},
};

static bool bad_argument(const char *option, const char *value, const char *why)
{
    fprintf(stderr, "wsgproxy: --%s %s: %s (see --help)\n", option, value, why);
    return false;
}

static const char *option_name(int opt)
{
    for (const struct option *o = long_options; o->name != NULL; o++) {
        if (o->val == opt) {
            return o->name;
        }
    }
    return "?";
}

/* A port 0..65535, or "off" (-1) where allowed. */
static bool parse_port(const char *option, const char *text, bool may_be_off, int *port)
{
    if (may_be_off && strcmp(text, "off") == 0) {
        *port = -1;
        return true;
    }
    char *end = NULL;
    errno = 0;
    long value = strtol(text, &end, 10);
    if (errno != 0 || end == text || *end != '\0' || value < 0 || value > 65535) {
        return bad_argument(option, text,
                            may_be_off ? "a port is 0 to 65535, or off" : "a port is 0 to 65535");
    }
    *port = (int)value;
    return true;
}

/* -1: not given on the command line, the default follows another port. */
static void default_options(proxy_options_t *o)
{
    *o = (proxy_options_t){.listen = "0.0.0.0",
                           .tcp_port = 1000,
                           .gripper_tcp_port = 1000,
                           .udp_port = -2,
                           .gripper_udp_port = -2,
                           .bin_port = 1500,
                           .gripper_bin_port = 1500,
                           .bin_reply_port = 1501,
                           .gripper_bin_reply_port = 1501};
}

static int *port_of(proxy_options_t *o, int opt)
{
    switch (opt) {
    case OPT_TCP:
        return &o->tcp_port;
    case OPT_UDP:
        return &o->udp_port;
    case OPT_BIN:
        return &o->bin_port;
    case OPT_BIN_REPLY:
        return &o->bin_reply_port;
    case OPT_G_TCP:
        return &o->gripper_tcp_port;
    case OPT_G_UDP:
        return &o->gripper_udp_port;
    case OPT_G_BIN:
        return &o->gripper_bin_port;
    default:
        return &o->gripper_bin_reply_port;
    }
}

/* 0: go on; else the exit status (1 is never used: 0 help, 2 error). */
static int parse_options(int argc, char **argv, proxy_options_t *o)
{
    default_options(o);
    int opt;
    opterr = 0;
    while ((opt = getopt_long(argc, argv, "hV", long_options, NULL)) != -1) {
        opt = opt == 'h' ? OPT_HELP : opt == 'V' ? OPT_VERSION : opt;
        switch (opt) {
        case OPT_GRIPPER:
            o->gripper = optarg;
            break;
        case OPT_RECORD:
            o->record_path = optarg;
            break;
        case OPT_LISTEN:
            o->listen = optarg;
            break;
        case OPT_READY:
            o->ready_file = optarg;
            break;
        case OPT_HELP:
            fputs(usage, stdout);
            return -1;
        case OPT_VERSION:
            printf("wsgproxy %s\n", WSGSIM_VERSION);
            return -1;
        case '?':
            fprintf(stderr, "wsgproxy: unknown option or missing value: %s (see --help)\n",
                    argv[optind - 1]);
            return 2;
        default:
            if (!parse_port(option_name(opt), optarg, opt == OPT_UDP || opt == OPT_BIN,
                            port_of(o, opt))) {
                return 2;
            }
        }
    }
    if (optind < argc) {
        fprintf(stderr, "wsgproxy: unexpected argument %s (see --help)\n", argv[optind]);
        return 2;
    }
    if (o->gripper == NULL) {
        fprintf(stderr, "wsgproxy: --gripper HOST is required (see --help)\n");
        return 2;
    }
    return 0;
}

static bool resolve_gripper(proxy_t *p)
{
    struct addrinfo hints = {.ai_family = AF_UNSPEC, .ai_socktype = SOCK_STREAM};
    struct addrinfo *found = NULL;
    int rc = getaddrinfo(p->opt.gripper, NULL, &hints, &found);
    if (rc != 0) {
        fprintf(stderr, "wsgproxy: --gripper %s: %s\n", p->opt.gripper, gai_strerror(rc));
        return false;
    }
    memcpy(&p->gripper, found->ai_addr, found->ai_addrlen);
    p->gripper_len = found->ai_addrlen;
    freeaddrinfo(found);
    return true;
}

/* The ready line on stderr, and the ports in the ready file for a caller
 * that asked for free ones, written whole (a
 * temporary file renamed), so a reader never sees half of it. */
static bool announce_ready(const proxy_t *p)
{
    proxy_log("ready: tcp %s:%d, udp %s:%d, binary udp %s:%d; the gripper at %s", p->opt.listen,
              net_local_port(p->tcp_listener), p->opt.listen,
              p->udp_gcl >= 0 ? net_local_port(p->udp_gcl) : 0, p->opt.listen,
              p->udp_bin >= 0 ? net_local_port(p->udp_bin) : 0, p->opt.gripper);
    if (p->opt.ready_file == NULL) {
        return true;
    }
    char tmp[4096];
    snprintf(tmp, sizeof(tmp), "%s.tmp", p->opt.ready_file);
    FILE *f = fopen(tmp, "w");
    if (f == NULL) {
        fprintf(stderr, "wsgproxy: --ready-file %s: %s\n", tmp, strerror(errno));
        return false;
    }
    fprintf(f, "pid=%ld\ntcp_port=%d\nudp_port=%d\nbinary_udp_port=%d\n", (long)getpid(),
            net_local_port(p->tcp_listener), p->udp_gcl >= 0 ? net_local_port(p->udp_gcl) : 0,
            p->udp_bin >= 0 ? net_local_port(p->udp_bin) : 0);
    bool ok = fclose(f) == 0 && rename(tmp, p->opt.ready_file) == 0;
    if (!ok) {
        fprintf(stderr, "wsgproxy: --ready-file %s: %s\n", p->opt.ready_file, strerror(errno));
    }
    return ok;
}

static bool open_record(proxy_t *p)
{
    if (p->opt.record_path == NULL) {
        return true;
    }
    /* fully buffered: written after each wake-up, off the bytes' way */
    p->record = record_file_open(p->opt.record_path, "w", _IOFBF);
    if (p->record == NULL) {
        fprintf(stderr, "wsgproxy: --record %s: %s\n", p->opt.record_path, strerror(errno));
        return false;
    }
    fprintf(p->record,
            "# wsgproxy %s: the gripper at %s; sim_s: seconds since the proxy "
            "started\n",
            WSGSIM_VERSION, p->opt.gripper);
    return true;
}

static bool start(proxy_t *p)
{
    if (p->opt.udp_port == -2) {
        p->opt.udp_port = p->opt.tcp_port;
    }
    if (p->opt.gripper_udp_port == -2) {
        p->opt.gripper_udp_port = p->opt.gripper_tcp_port;
    }
    net_init(&p->net);
    p->start_ns = loop_monotonic_ns();
    p->tcp_listener = -1;
    return resolve_gripper(p) && split_init(&p->datagram) && (p->loop = loop_create()) != NULL &&
           loop_take_signals(p->loop) && proxy_tcp_start(p) && proxy_udp_start(p) &&
           open_record(p) && announce_ready(p);
}

static void run(proxy_t *p)
{
    while (!loop_stop_requested(p->loop)) {
        loop_wait(p->loop, p->record_dirty ? p->flush_ns : LOOP_NO_TIMEOUT);
        if (p->record_dirty && loop_monotonic_ns() >= p->flush_ns) {
            fflush(p->record);
            p->record_dirty = false;
        }
    }
}

int main(int argc, char **argv)
{
    host_log_init(); /* the event loop's own messages */
    int status = parse_options(argc, argv, &proxy.opt);
    if (status != 0) {
        return status < 0 ? 0 : status;
    }
    if (!start(&proxy)) {
        return 2;
    }
    run(&proxy);
    proxy_udp_stop(&proxy);
    split_free(&proxy.datagram);
    if (proxy.record != NULL && fclose(proxy.record) != 0) {
        fprintf(stderr, "wsgproxy: --record %s: %s\n", proxy.opt.record_path, strerror(errno));
        return 1;
    }
    if (proxy.opt.ready_file != NULL) {
        unlink(proxy.opt.ready_file);
    }
    return 0;
}
