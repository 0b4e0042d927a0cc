/* SPDX-License-Identifier: BSD-3-Clause */
/* libFuzzer target: arbitrary bytes on the simulation control channel,
 * assembled into lines by the channel's line buffer and handled as
 * host/simctl/control.c handles them (mirrored in handle_line() below:
 * control.c itself is the socket side), so that every command of
 * host/simctl/commands*.c runs against the real host: fleet, finger bus,
 * faults, delays, on the paused simulated clock.
 *
 * Input layout: byte 0 picks the number of devices (bits 0-1: 1..4), the
 * fingers (bit 2: none) and the world (bit 3: the default physics scene,
 * --physics mujoco, so that the scene's commands act on one). The rest is a list of segments
 * separated by 0xFF (a byte no control line may hold); a segment's first byte says where its bytes
 * go: bit 0 clear, the control channel, assembled into lines as the channel does; bit 0 set, one of
 * two device sessions on device 0 (bit 1: the TCP-like stream or the UDP-like datagram), so that
 * session commands (SESSIONS?, DELAY, FAILNEXT, CUT) have sessions to act on.
 *
 * Checked: every line gets one reply, a single line; a STEP that the line
 * deferred ends; device output is whole bounded lines. A RESUME lets wall
 * time in, so the clock is paused again after every line: inputs replay. */
#include <stdlib.h>
#include <string.h>

#include "fuzz_host.h"
#include "gripper.h"
#include "fleet.h"
#include "clock.h"
#include "simctl/commands.h"
#include "simctl/scheduler.h"
#include "wsg/gcl_linebuf.h"
#include "wsg/wsg_conn.h"
#include "wsg/wsg_gcl.h"

#define SEPARATOR 0xffu
#define REPLY_MAX (1u << 20) /* STATE? of every session is about 70 KB */
#define SESSIONS 2

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static gcl_linebuf_t input;
static unsigned selected;
static wsg_conn_t sessions[SESSIONS];

static void check_reply(const char *reply)
{
    if (reply == NULL || strlen(reply) > REPLY_MAX || strpbrk(reply, "\r\n") != NULL) {
        abort(); /* one line per command line, always */
    }
}

static void session_write(void *ctx, const char *bytes, size_t len, wsg_msg_kind_t kind)
{
    (void)ctx;
    (void)kind;
    if (len == 0 || len > WSG_REPLY_MAX || bytes[len - 1] != '\n') {
        abort();
    }
}

static const wsg_conn_io_t session_io = {.write = session_write};

/* What control.c's handle_line() does with a line, the reply checked. */
static void handle_line(void)
{
    if (wsg_gcl_linebuf_status(&input) != GCL_LINE_OK || strspn(input.text, " \t") == input.len) {
        return; /* the channel answers these itself, or not at all */
    }
    simctl_outcome_t outcome = {false, false};
    char *reply = simctl_exec(fuzz_host_sim(), input.text, input.len, &selected, &outcome);
    if (outcome.deferred) {
        if (reply != NULL) {
            abort(); /* a deferred STEP answers when it has run */
        }
        simctl_step_finish(simctl_scheduler(fuzz_host_sim()));
        if (simctl_step_running(simctl_scheduler(fuzz_host_sim()))) {
            abort();
        }
        reply = simctl_step_reply(fuzz_host_sim());
    }
    check_reply(reply);
    free(reply);
    if (!simclock_paused(simctl_clock(fuzz_host_sim()))) {
        simclock_pause(simctl_clock(fuzz_host_sim()));
    }
}

static void control_bytes(const uint8_t *p, size_t n)
{
    for (size_t i = 0; i < n; i++) {
        if (wsg_gcl_linebuf_feed(&input, p[i])) {
            handle_line();
        }
    }
}

static void session_bytes(unsigned slot, const uint8_t *p, size_t n)
{
    gripper_t *g = fleet_gripper(fuzz_host_fleet(), 0);
    if (!wsg_conn_is_open(&sessions[slot])) {
        return; /* RESET or CUT closed it */
    }
    gripper_feed(g, &sessions[slot], p, n, slot == 1);
    gripper_input_done(g);
    if (wsg_conn_wants_close(&sessions[slot])) {
        wsg_conn_close(&sessions[slot], WSG_CLOSE_ANNOUNCED); /* BYE(), as the port does */
    }
    fuzz_host_settle();
}

static void run_segment(const uint8_t *seg, size_t len)
{
    if (len == 0) {
        return;
    }
    if ((seg[0] & 1u) == 0) {
        control_bytes(seg + 1, len - 1);
    } else {
        session_bytes((seg[0] >> 1) & 1u, seg + 1, len - 1);
    }
}

static void start(uint8_t config)
{
    char devices[2] = {(char)('1' + (config & 3u)), '\0'};
    char *argv[] = {"wsgsim",    "--no-udp",
                    "--devices", devices,
                    "--fingers", (config & 4u) != 0 ? "none,none" : "fmf,dsa",
                    "--physics", (config & 8u) != 0 ? "mujoco" : "builtin",
                    NULL};
    const host_options_t *opts = fuzz_host_options(8, argv);
    if (opts == NULL) {
        abort();
    }
    fuzz_host_start(opts);
    gripper_t *g = fleet_gripper(fuzz_host_fleet(), 0);
    wsg_conn_open(&sessions[0], &g->device, &wsg_gcl_driver, WSG_TRANSPORT_STREAM, &session_io,
                  NULL);
    wsg_conn_open(&sessions[1], &g->device, &wsg_gcl_driver, WSG_TRANSPORT_DATAGRAM, &session_io,
                  NULL);
    wsg_gcl_linebuf_reset(&input);
    selected = 0;
}

static void stop(void)
{
    for (unsigned i = 0; i < SESSIONS; i++) {
        wsg_conn_close(&sessions[i], WSG_CLOSE_DROPPED); /* no-op when RESET or CUT closed it */
    }
    fuzz_host_stop();
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size == 0) {
        return 0;
    }
    start(data[0]);
    size_t first = 1;
    for (size_t i = 1; i <= size; i++) {
        if (i == size || data[i] == SEPARATOR) {
            run_segment(data + first, i - first);
            first = i + 1;
        }
    }
    stop(); /* a last line without its end is not run, as on the channel */
    return 0;
}
