/* SPDX-License-Identifier: BSD-3-Clause */
/* libFuzzer target: arbitrary bytes through the session input path of the
 * device core (line assembly, parser, dispatcher, motion and grip state
 * machine, AUTOSEND) on a virtual clock.
 *
 * The finger bus runs too: the host's loopback CAN bus with two simulated
 * finger nodes (host/can/can_loopback.c), plus raw frames from the input.
 *
 * Input layout: byte 0 picks the model (bits 0-3), whether the binary
 * protocol ignores checksums (bit 4: the device's own setting, so that
 * mutated frames reach the command handlers instead of failing their CRC),
 * the finger pair (bits 5-6) and whether a dropped connection raises FAST
 * STOP (bit 7). The rest is a
 * list of segments separated by 0xFF; each segment starts with a control byte:
 *   bits 0-1  session 0..3 (0 and 1 stream, 2 and 3 datagram)
 *   bits 2-3  0 feed, 1 feed and end the datagram, 2 close and reopen the
 *             session (close reason from the payload length; on session 3:
 *             deliver the payload to the core as raw CAN frames of 13 bytes:
 *             id (4, little endian), flags, dlc, data (7 of 8)), 3 feed, then
 *             run HOME-length time
 *   bits 4-7  virtual time to run afterwards (index into run_ms)
 * and the payload bytes follow. Sessions choose their protocol by their first
 * byte (0xAA: the binary protocol, else GCL). Every line the core writes is
 * checked: one whole, printable, '\n'-terminated line no longer than
 * WSG_REPLY_MAX; every binary frame: one whole frame with a valid CRC.
 *
 * The report on the driver under test (host/diag/driver_report.c) watches
 * every session; at the end of the input every session closes, the report
 * is written as JSON and as text, and its request count must be the number
 * of whole messages the sessions took in. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "bin/wsg_bin_frame.h"
#include "can_loopback.h"
#include "driver_report.h"
#include "hal_can.h"
#include "hal_clock.h"
#include "hal_log.h"
#include "sim/sim_models.h"
#include "sim/sim_world.h"
#include "wsg/wsg_bin.h"
#include "wsg/wsg_conn.h"
#include "wsg/wsg_gcl.h"

#define FUZZ_SESSIONS 4
#define SEPARATOR 0xffu
#define START_US 5000000u
#define MOTION_TICK_MAX_US 1000u
#define RAW_FRAME_BYTES 13u
#define RAW_FRAMES_MAX 64u

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static wsg_device_t device;
static sim_world_t world;
static uint64_t now_us;
static can_loopback_t *loopback; /* the fingers of this input, freed by the next */
static wsg_conn_t sessions[FUZZ_SESSIONS];
static driver_report_t *report; /* this input's, freed at its end */
static unsigned long messages_seen;
static const char *const finger_pairs[4] = {"fmf,dsa", "dsa,generic", "none,fmf", "generic,none"};
static struct {
    hal_can_frame_t frames[RAW_FRAMES_MAX];
    unsigned head, count;
    hal_can_filter_t filters[HAL_CAN_MAX_FILTERS];
    unsigned filter_count;
    const hal_can_t *loopback;
} raw;
static const uint32_t run_ms[16] = {0,   1,   2,   5,    10,   20,   50,   100,
                                    200, 300, 500, 1000, 2000, 3000, 5000, 10000};

uint64_t hal_clock_now_us(void)
{
    return now_us;
}

void hal_log(hal_log_level_t level, const char *message)
{
    (void)level;
    if (strlen(message) > 1024) {
        abort(); /* a log line must be a bounded C string */
    }
}

static void check_frame(const uint8_t *frame, size_t len)
{
    if (len < WSG_BIN_HEADER_LEN + WSG_BIN_STATUS_LEN + WSG_BIN_CRC_LEN ||
        len > WSG_BIN_REPLY_MAX || frame[1] != WSG_BIN_PREAMBLE_BYTE ||
        frame[2] != WSG_BIN_PREAMBLE_BYTE ||
        wsg_bin_get_u16(frame + 4) + WSG_BIN_HEADER_LEN + WSG_BIN_CRC_LEN != len ||
        wsg_bin_crc(frame, len) != 0) {
        abort();
    }
}

static void check_line(void *ctx, const char *line, size_t len, wsg_msg_kind_t kind)
{
    (void)ctx;
    if (len > 0 && (unsigned char)line[0] == WSG_BIN_PREAMBLE_BYTE) {
        check_frame((const uint8_t *)line, len);
        return;
    }
    if (len == 0 || len > WSG_REPLY_MAX || line[len - 1] != '\n') {
        abort();
    }
    for (size_t i = 0; i + 1 < len; i++) {
        unsigned char c = (unsigned char)line[i];
        if (c < 0x20u || c >= 0x7fu) {
            abort();
        }
    }
    if (kind == WSG_MSG_UPDATE && line[0] != '@') {
        abort();
    }
}

static const wsg_conn_io_t fuzz_io = {.write = check_line};

/* The core's CAN controller: the loopback bus, with raw frames from the
 * input received first (through the filters, as a driver applies them). */
static bool can_send(void *ctx, const hal_can_frame_t *frame)
{
    (void)ctx;
    if (frame->dlc > HAL_CAN_MAX_DLC) {
        abort(); /* the core never builds an invalid frame */
    }
    return hal_can_send(raw.loopback, frame);
}

static bool can_recv(void *ctx, hal_can_frame_t *frame)
{
    (void)ctx;
    while (raw.count > 0) {
        *frame = raw.frames[raw.head];
        raw.head = (raw.head + 1u) % RAW_FRAMES_MAX;
        raw.count--;
        if (hal_can_filters_accept(raw.filters, raw.filter_count, frame)) {
            return true;
        }
    }
    return hal_can_recv(raw.loopback, frame);
}

static bool can_set_filters(void *ctx, const hal_can_filter_t *filters, unsigned count)
{
    (void)ctx;
    if (count > HAL_CAN_MAX_FILTERS) {
        return false;
    }
    memcpy(raw.filters, filters, count * sizeof(*filters));
    raw.filter_count = count;
    return hal_can_set_filters(raw.loopback, filters, count);
}

static const hal_can_ops_t fuzz_can_ops = {can_send, can_recv, can_set_filters, false, NULL, NULL,
                                           NULL,     NULL};

static void queue_raw_frames(const uint8_t *p, size_t n)
{
    for (; n >= RAW_FRAME_BYTES && raw.count < RAW_FRAMES_MAX;
         p += RAW_FRAME_BYTES, n -= RAW_FRAME_BYTES) {
        hal_can_frame_t f;
        memset(&f, 0, sizeof(f));
        f.id = (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
        f.flags = p[4] & (HAL_CAN_FLAG_EXT | HAL_CAN_FLAG_RTR);
        f.id &= (f.flags & HAL_CAN_FLAG_EXT) != 0 ? HAL_CAN_EXT_ID_MASK : HAL_CAN_STD_ID_MASK;
        f.dlc = p[5] % (HAL_CAN_MAX_DLC + 1u);
        memcpy(f.data, p + 6, RAW_FRAME_BYTES - 6u);
        raw.frames[(raw.head + raw.count) % RAW_FRAMES_MAX] = f;
        raw.count++;
    }
}

static wsg_transport_t transport_of(unsigned slot)
{
    return slot < 2 ? WSG_TRANSPORT_STREAM : WSG_TRANSPORT_DATAGRAM;
}

/* ---- the driver report's observers, as the coverage forwards them ---- */

static void report_read(void *ctx, const wsg_conn_t *c, const uint8_t *bytes, size_t len)
{
    driver_report_read(ctx, 0, c, bytes, len);
}

static void report_in(void *ctx, const wsg_conn_t *c, const char *bytes, size_t len)
{
    messages_seen++;
    driver_report_message_in(ctx, 0, c, bytes, len);
}

static void report_out(void *ctx, const wsg_conn_t *c, const char *bytes, size_t len)
{
    driver_report_message_out(ctx, 0, c, bytes, len);
}

static void report_closed(void *ctx, const wsg_conn_t *c, wsg_close_reason_t why, bool fast_stop)
{
    driver_report_closed(ctx, 0, c, why, fast_stop);
}

static void report_command(void *ctx, const wsg_conn_t *c, const char *name, int index,
                           unsigned form, unsigned argc, wsg_status_t status)
{
    (void)name, (void)argc;
    if (driver_report_watches(driver_report_watch(ctx, 0), index)) {
        driver_report_gcl_command(ctx, 0, c, index, form, status);
    }
}

static void report_error(void *ctx, const wsg_conn_t *c, int index, wsg_status_t status)
{
    (void)index;
    driver_report_gcl_error(ctx, 0, c, status);
}

static wsg_conn_observer_t report_conn = {.message_in = report_in,
                                          .message_out = report_out,
                                          .read = report_read,
                                          .closed = report_closed};
static wsg_gcl_observer_t report_gcl = {.command_done = report_command, .error_sent = report_error};

static void watch_sessions(void)
{
    report = driver_report_create(1);
    if (report == NULL) {
        abort();
    }
    messages_seen = 0;
    driver_report_attach(report, &device, 0);
    report_conn.ctx = report;
    report_gcl.ctx = report;
    wsg_conn_add_observer(&device, &report_conn);
    wsg_gcl_add_observer(&device, &report_gcl);
}

/* Every session closes; the report is written both ways, and it counted
 * every whole message as a request. */
static void close_the_report(void)
{
    for (unsigned i = 0; i < FUZZ_SESSIONS; i++) {
        wsg_conn_close(&sessions[i], WSG_CLOSE_DROPPED);
    }
    cJSON *json = driver_report_json(report);
    const cJSON *requests = cJSON_GetObjectItem(cJSON_GetObjectItem(json, "total"), "requests");
    if (requests == NULL || requests->valuedouble != (double)messages_seen) {
        abort();
    }
    char *text = cJSON_PrintUnformatted(json);
    char *summary = driver_report_text(report);
    if (text == NULL || summary == NULL) {
        abort();
    }
    free(text);
    free(summary);
    cJSON_Delete(json);
    wsg_conn_remove_observer(&device, &report_conn);
    wsg_gcl_remove_observer(&device, &report_gcl);
    driver_report_destroy(report);
    report = NULL;
}

static void open_slot(unsigned slot)
{
    wsg_conn_open(&sessions[slot], &device, NULL, transport_of(slot), &fuzz_io, NULL);
}

/* Runs the port's loop: steps at every deadline the core asks for. */
static void run_for(uint64_t us)
{
    uint64_t end = now_us + us;
    while (now_us < end) {
        uint64_t next = wsg_device_next_deadline_us(&device);
        if (next > end) {
            next = end;
        }
        if (next > now_us + 100000u * MOTION_TICK_MAX_US) {
            next = now_us + 100000u * MOTION_TICK_MAX_US;
        }
        now_us = next > now_us ? next : now_us + 1u;
        wsg_sim_world_advance(&world, now_us);
        wsg_device_step(&device);
    }
}

static void close_reopen(unsigned slot, size_t payload_len)
{
    static const wsg_close_reason_t reasons[3] = {WSG_CLOSE_ANNOUNCED, WSG_CLOSE_DROPPED,
                                                  WSG_CLOSE_EXPIRED};
    wsg_conn_close(&sessions[slot], reasons[payload_len % 3]);
    open_slot(slot);
}

static void run_segment(const uint8_t *seg, size_t len)
{
    if (len == 0) {
        return;
    }
    unsigned slot = seg[0] & 3u;
    unsigned op = (seg[0] >> 2) & 3u;
    const uint8_t *payload = seg + 1;
    size_t n = len - 1;
    if (op == 2 && slot == 3) {
        queue_raw_frames(payload, n);
    } else if (op == 2) {
        close_reopen(slot, n);
    } else {
        wsg_sim_world_advance(&world, now_us);
        wsg_conn_input(&sessions[slot], payload, n);
        if (op == 1) {
            wsg_conn_end_datagram(&sessions[slot]);
        }
    }
    /* the port reopens a session the client closed with BYE() */
    if (wsg_conn_wants_close(&sessions[slot])) {
        close_reopen(slot, 0);
    }
    run_for((uint64_t)run_ms[seg[0] >> 4] * 1000u + (op == 3 ? 3000000u : 0u));
    driver_report_flags(report, 0, wsg_device_flags(&device)); /* as the port samples them */
}

static void power_on(uint8_t config_byte)
{
    wsg_config_t cfg;
    unsigned model = (config_byte & 0x0fu) % wsg_sim_model_count();
    fbus_type_t types[FBUS_SLOTS];
    finger_node_params_t params;
    wsg_finger_node_defaults(&params);
    if (!wsg_finger_node_parse_pair(finger_pairs[(config_byte >> 5) & 3u], types)) {
        abort();
    }
    wsg_sim_model_config(wsg_sim_model_at(model), &cfg);
    cfg.bin_crc_unchecked = (config_byte & 0x10u) != 0;
    cfg.disconnect_raises_faststop = (config_byte & 0x80u) != 0;
    now_us = START_US;
    wsg_sim_world_init(&world, &cfg, now_us);
    memset(&raw, 0, sizeof(raw));
    can_loopback_destroy(loopback);
    loopback = can_loopback_create(types, &params);
    if (loopback == NULL) {
        abort();
    }
    raw.loopback = can_loopback_bus(loopback);
    wsg_hal_t hal;
    wsg_sim_world_hal(&world, &hal);
    hal.can = (hal_can_t){&fuzz_can_ops, NULL};
    wsg_device_init(&device, &cfg, &hal);
    static const wsg_proto_driver_t *const drivers[] = {&wsg_bin_driver, &wsg_gcl_driver};
    wsg_conn_set_drivers(&device, drivers, sizeof(drivers) / sizeof(drivers[0]));
    watch_sessions();
    for (unsigned i = 0; i < FUZZ_SESSIONS; i++) {
        open_slot(i);
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size == 0) {
        return 0;
    }
    power_on(data[0]);
    size_t start = 1;
    for (size_t i = 1; i <= size; i++) {
        if (i == size || data[i] == SEPARATOR) {
            run_segment(data + start, i - start);
            start = i + 1;
        }
    }
    run_for(100000u); /* let pending AUTOSEND and final replies go out */
    close_the_report();
    return 0;
}
