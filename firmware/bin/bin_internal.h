/* SPDX-License-Identifier: BSD-3-Clause */
/* The binary driver's own declarations: its per-connection state, the
 * command table's handler type and the reply helpers. Nothing outside
 * firmware/bin includes this. */
#ifndef BIN_INTERNAL_H
#define BIN_INTERNAL_H

#include "bin/wsg_bin_frame.h"
#include "priv/conn.h"
#include "priv/timer.h"
#include "wsg/wsg_bin.h"

/* Values with automatic updates (spec §6), in the order of their IDs. */
typedef enum {
    BIN_SUB_STATE,
    BIN_SUB_GRASP,
    BIN_SUB_WIDTH,
    BIN_SUB_SPEED,
    BIN_SUB_FORCE,
    BIN_SUB_COUNT
} bin_sub_value_t;

typedef struct {
    bool on;
    bool on_change;
    uint32_t period_us;
    uint64_t next_due_us;
    float last_number; /* the last value sent (change-sensitive mode) */
    uint32_t last_bits;
} bin_sub_t;

/* A binary connection's state, inside its wsg_conn_t. */
typedef struct {
    conn_t *conn;
    wsg_bin_framer_t framer;
    bool announced;       /* 0x07 answered: E_ACCESS_DENIED until the close */
    uint8_t pending_id;   /* the long command whose final frame is due */
    wsg_bin_frame_t held; /* the request waiting for the command processor */
    bin_sub_t subs[BIN_SUB_COUNT];
    wsg_timer_t timer; /* due at the earliest subscription */
} bin_conn_t;

_Static_assert(sizeof(bin_conn_t) <= CONN_PROTO_BYTES,
               "WSG_CONN_STORAGE_BYTES (wsg_opts.h) is too small for a binary connection");

static inline bin_conn_t *bin_of(wsg_conn_t *c)
{
    return (bin_conn_t *)(void *)conn_of(c)->proto;
}

static inline const bin_conn_t *bin_of_const(const wsg_conn_t *c)
{
    return (const bin_conn_t *)(const void *)conn_of_const(c)->proto;
}

static inline wsg_device_t *bin_device(const bin_conn_t *b)
{
    return dev_public(b->conn->dev);
}

/* One request being handled. A handler either returns a status (the
 * driver sends a status-only reply) or sends its own reply and returns
 * BIN_REPLIED. */
typedef struct {
    bin_conn_t *bin;
    wsg_device_t *dev;
    uint8_t id;
    const uint8_t *payload;
    uint16_t length;
} bin_req_t;

#define BIN_REPLIED ((wsg_status_t)-1)
/* The request waits for the script, which answers it (bin_script.c). */
#define BIN_QUEUED ((wsg_status_t)-2)

typedef wsg_status_t (*bin_handler_t)(bin_req_t *req);

/* commands.c: the built-in commands */
typedef struct {
    uint8_t id;
    const char *name; /* as tools/wsgbin names it */
    bin_handler_t handler;
} bin_command_t;
/* The built-in command with this ID, NULL for none. */
const bin_command_t *wsg_bin_find_command(uint8_t id);

/* reply.c: sending */
void wsg_bin_send(bin_conn_t *b, uint8_t id, wsg_status_t status, const uint8_t *values, size_t len,
                  wsg_msg_kind_t kind);
/* Replies E_SUCCESS with values and returns BIN_REPLIED. */
wsg_status_t wsg_bin_reply_values(bin_req_t *req, const uint8_t *values, size_t len);
wsg_status_t wsg_bin_reply_f32(bin_req_t *req, float value);

/* Length checks: E_NO_PARAM_EXPECTED / E_CMD_FORMAT_ERROR. */
wsg_status_t wsg_bin_expect_none(const bin_req_t *req);
wsg_status_t wsg_bin_expect_len(const bin_req_t *req, uint16_t len);
/* A finite float at offset, else E_INVALID_PARAMETER. */
wsg_status_t wsg_bin_get_finite(const bin_req_t *req, size_t offset, float *out);
float wsg_bin_clamp(float value, float low, float high);

/* bin_motion.c 0x20-0x26 */
wsg_status_t wsg_bin_homing(bin_req_t *req);
wsg_status_t wsg_bin_preposition(bin_req_t *req);
wsg_status_t wsg_bin_stop(bin_req_t *req);
wsg_status_t wsg_bin_fast_stop(bin_req_t *req);
wsg_status_t wsg_bin_ack(bin_req_t *req);
wsg_status_t wsg_bin_grasp(bin_req_t *req);
wsg_status_t wsg_bin_release(bin_req_t *req);
/* bin_settings.c 0x30-0x38 */
wsg_status_t wsg_bin_set_acc(bin_req_t *req);
wsg_status_t wsg_bin_get_acc(bin_req_t *req);
wsg_status_t wsg_bin_set_force(bin_req_t *req);
wsg_status_t wsg_bin_get_force_limit(bin_req_t *req);
wsg_status_t wsg_bin_set_soft_limits(bin_req_t *req);
wsg_status_t wsg_bin_get_soft_limits(bin_req_t *req);
wsg_status_t wsg_bin_clear_soft_limits(bin_req_t *req);
wsg_status_t wsg_bin_overdrive(bin_req_t *req);
wsg_status_t wsg_bin_tare(bin_req_t *req);
/* bin_state.c 0x40-0x46 and automatic updates */
wsg_status_t wsg_bin_get_state(bin_req_t *req);
wsg_status_t wsg_bin_get_grasp_state(bin_req_t *req);
wsg_status_t wsg_bin_get_stats(bin_req_t *req);
wsg_status_t wsg_bin_get_width(bin_req_t *req);
wsg_status_t wsg_bin_get_speed(bin_req_t *req);
wsg_status_t wsg_bin_get_force(bin_req_t *req);
wsg_status_t wsg_bin_get_temp(bin_req_t *req);
void wsg_bin_updates_fire(wsg_timer_t *timer, uint64_t now_us);
void wsg_bin_updates_stop(bin_conn_t *b);
bool wsg_bin_updates_any(const bin_conn_t *b);
/* bin_system.c 0x06, 0x07, 0x50-0x53 */
wsg_status_t wsg_bin_loop(bin_req_t *req);
wsg_status_t wsg_bin_disconnect(bin_req_t *req);
wsg_status_t wsg_bin_system_info(bin_req_t *req);
wsg_status_t wsg_bin_set_tag(bin_req_t *req);
wsg_status_t wsg_bin_get_tag(bin_req_t *req);
wsg_status_t wsg_bin_get_limits(bin_req_t *req);
/* bin_finger.c 0x60-0x63, 0x70-0x73 */
wsg_status_t wsg_bin_finger_info(bin_req_t *req);
wsg_status_t wsg_bin_finger_flags(bin_req_t *req);
wsg_status_t wsg_bin_finger_power(bin_req_t *req);
wsg_status_t wsg_bin_finger_data(bin_req_t *req);

/* bin_script.c: the custom command channel of a user script */
wsg_status_t wsg_bin_script_queue(bin_conn_t *b, const wsg_bin_frame_t *frame);
void wsg_bin_script_note_host(bin_conn_t *b);
void wsg_bin_script_drop_conn(bin_conn_t *b);

#endif
