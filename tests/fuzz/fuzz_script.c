/* SPDX-License-Identifier: BSD-3-Clause */
/* libFuzzer target: a user script and what reaches it. The script's
 * bindings (host/script*.c: mc, gripper, finger, grasping, cmd, the byte
 * helpers, the environment's shims and bounded library functions, the
 * coroutine relay) parse whatever a script passes them, and the custom
 * command channel parses whatever a binary client sends the script.
 *
 * Input layout: segments separated by 0xFF. The first is the script's text
 * (Lua source; a precompiled chunk is refused), run on device 0 of the
 * host as build/wsgsim runs it, on the paused simulated clock, under the
 * process's watchdog and memory budget. Each later segment's first byte
 * says what comes: bit 0 clear, the rest are bytes of a binary client
 * (frames to the script's IDs among them); bit 0 set, the rest's first
 * byte is a number of simulated milliseconds to step, after which the loop
 * continues the preempted script a few passes, as the event loop does.
 *
 * Checked: the script ends by STOP; then no interpreter holds memory (the
 * process's count is back to 0) and the device answers a query. */
#include <stdlib.h>
#include <string.h>

#include "fleet.h"
#include "fuzz_host.h"
#include "gripper.h"
#include "script.h"
#include "wsg/wsg_bin.h"
#include "wsg/wsg_conn.h"

#define SEPARATOR 0xffu
#define PASSES_PER_STEP 4u /* continuations after a step: each at most a slice */

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static wsg_conn_t session;
static size_t replied; /* bytes the device sent the client */

static void session_write(void *ctx, const char *bytes, size_t len, wsg_msg_kind_t kind)
{
    (void)ctx;
    (void)bytes;
    (void)kind;
    replied += len;
}

static const wsg_conn_io_t session_io = {.write = session_write};

static gripper_t *device0(void)
{
    return fleet_gripper(fuzz_host_fleet(), 0);
}

static void start(void)
{
    char *argv[] = {"wsgsim", "--no-udp", "--fingers", "fmf,fmf", NULL};
    const host_options_t *opts = fuzz_host_options(4, argv);
    if (opts == NULL) {
        abort();
    }
    fuzz_host_start(opts);
    wsg_conn_open(&session, &device0()->device, &wsg_bin_driver, WSG_TRANSPORT_STREAM, &session_io,
                  NULL);
    replied = 0;
}

static void client_bytes(const uint8_t *p, size_t n)
{
    gripper_t *g = device0();
    if (!wsg_conn_is_open(&session)) {
        return; /* 0x07 and the close after it */
    }
    gripper_feed(g, &session, p, n, 0);
    gripper_input_done(g);
    fuzz_host_settle();
}

static void step(uint8_t ms)
{
    fuzz_host_step((uint64_t)ms * 1000u);
    for (unsigned i = 0; i < PASSES_PER_STEP; i++) {
        fleet_run_scripts(fuzz_host_fleet());
        fuzz_host_settle();
    }
}

static void run_segment(const uint8_t *seg, size_t len)
{
    if (len == 0) {
        return;
    }
    if ((seg[0] & 1u) == 0) {
        client_bytes(seg + 1, len - 1);
    } else if (len > 1) {
        step(seg[1]);
    }
}

static void run_script(const uint8_t *code, size_t len)
{
    char why[512];
    fleet_note_scripting(fuzz_host_fleet());
    const char *path = fuzz_host_file(code, len);
    (void)gripper_run_script(device0(), path, why, sizeof(why));
    fuzz_host_close_file();
    fuzz_host_settle();
}

/* The script stopped, nothing of it is left, and the device still serves. */
static void check_and_stop(void)
{
    gripper_t *g = device0();
    if (g->script != NULL) {
        (void)script_stop(g->script);
        script_info_t info;
        script_info(g->script, &info);
        if (info.running || info.memory != 0 || info.process.memory != 0) {
            abort();
        }
    }
    if (wsg_conn_is_open(&session)) {
        wsg_conn_close(&session, WSG_CLOSE_DROPPED);
    }
    /* a new client (the old one may be inside a frame): 0x40 with a CRC
     * of 0, answered (with an error) by a device that still serves */
    static const uint8_t query[] = {0xaa, 0xaa, 0xaa, 0x40, 0x03, 0x00,
                                    0x00, 0x00, 0x00, 0x00, 0x00};
    wsg_conn_open(&session, &g->device, &wsg_bin_driver, WSG_TRANSPORT_STREAM, &session_io, NULL);
    size_t before = replied;
    client_bytes(query, sizeof(query));
    if (replied == before) {
        abort();
    }
    wsg_conn_close(&session, WSG_CLOSE_DROPPED);
    fuzz_host_stop();
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    size_t end = 0;
    while (end < size && data[end] != SEPARATOR) {
        end++;
    }
    start();
    run_script(data, end);
    size_t first = end + 1;
    for (size_t i = first; i <= size; i++) {
        if (i == size || data[i] == SEPARATOR) {
            run_segment(data + first, i - first);
            first = i + 1;
        }
    }
    check_and_stop();
    return 0;
}
