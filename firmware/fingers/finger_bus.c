/* SPDX-License-Identifier: BSD-3-Clause */
/* The gripper side of the finger bus (finger_bus.h). */
#include "priv/finger_bus.h"

#include <string.h>

#include "hal_log.h"
#include "wsg/wsg_textbuf.h"

/* On an on-demand bus the controller ticks this long after a change (start,
 * fault injection, a finger's flags or type, TARE): enough for a node to boot
 * (20 ms), a descriptor retry (100 ms) and a comm fault (300-310 ms) to show. */
#define FBUS_SETTLE_US 500000u

/* The quiet time of a bus that keeps none: every step polls. */
static const uint64_t never_quiet_us;

/* The bus ticks while it settles after a change (wake, awake_until_us) or
 * the force loop runs; a real bus always. What it follows changes in a full
 * step (a broadcast is always in one) and at a TARE between steps. */
static void note_deadline(finger_bus_t *bus)
{
    bool ticking = !bus->can->ops->on_demand || bus->regulating || bus->wake ||
                   bus->next_state_us < bus->awake_until_us;
    bus->deadline_us = ticking ? bus->next_state_us : UINT64_MAX;
}

void wsg_finger_bus_init(finger_bus_t *bus, const hal_can_t *can)
{
    memset(bus, 0, sizeof(*bus));
    bus->can = can;
    bus->bus_quiet_until_us = &never_quiet_us;
    bus->deadline_us = UINT64_MAX;
    if (can == NULL) {
        return;
    }
    bus->bus_quiet_until_us = hal_can_quiet_until_us(can, &never_quiet_us);
    /* the last one only on an on-demand bus: the simulation's fault
     * injections, which change the bus without a node saying so */
    static const hal_can_filter_t filters[] = {
        {FBUS_ID_DESCRIPTOR, 0x7FCu, 0}, {FBUS_ID_MEASURE, 0x7FCu, 0}, {FBUS_ID_BULK, 0x7FCu, 0},
        {FBUS_ID_HEARTBEAT, 0x7FCu, 0},  {FBUS_ID_SIMCTL, 0x7FCu, 0},
    };
    unsigned count = sizeof(filters) / sizeof(filters[0]);
    hal_can_set_filters(can, filters, can->ops->on_demand ? count : count - 1u);
    bus->power_mask = (uint8_t)((1u << FBUS_SLOTS) - 1u);
    bus->wake = true;
    note_deadline(bus);
}

static void send(finger_bus_t *bus, const hal_can_frame_t *frame)
{
    if (hal_can_send(bus->can, frame)) {
        bus->tx_frames++;
    }
}

static void slot_log(hal_log_level_t level, unsigned slot, const char *what)
{
    char storage[80];
    wsg_textbuf_t tb;
    wsg_textbuf_init(&tb, storage, sizeof(storage));
    wsg_textbuf_put_str(&tb, "finger ");
    wsg_textbuf_put_uint(&tb, slot);
    wsg_textbuf_put_str(&tb, ": ");
    wsg_textbuf_put_str(&tb, what);
    hal_log(level, storage);
}

/* TARE() comes between two steps, at a time the bus does not know (an
 * on-demand bus may have slept for long): its wait starts at the next step. */
#define FBUS_TARE_UNSTAMPED UINT64_MAX

/* The command goes out once per request and again while the node's
 * MEASURE frames do not count it: CAN acknowledges a frame on the wire, not
 * that the node's software took it. */
static void send_tare(finger_bus_t *bus, unsigned slot, uint64_t sent_us)
{
    fbus_slot_t *s = &bus->slot[slot];
    hal_can_frame_t f;
    wsg_fbus_pack_command(&f, FBUS_NODE_ID(slot), FBUS_CMD_TARE);
    send(bus, &f);
    s->tare_sends++;
    s->tare_sent_us = sent_us;
    bus->wake = true;
    bus->quiet_until_us = 0; /* TARE() comes between steps: the next one is not quiet */
    note_deadline(bus);
}

static void repeat_tare(finger_bus_t *bus, unsigned slot, uint64_t now_us)
{
    fbus_slot_t *s = &bus->slot[slot];
    if (s->tare_sends < FBUS_TARE_SENDS) {
        send_tare(bus, slot, now_us);
        return;
    }
    s->tare_pending = false;
    slot_log(HAL_LOG_WARN, slot, "TARE not confirmed by the finger");
}

/* Forgets what the node told (a reboot may bring another finger). */
static void forget_node(fbus_slot_t *s, wsg_finger_t *finger)
{
    s->config = false;
    s->unpublished = true;
    s->desc_request_us = 0;
    s->tare_pending = false;
    wsg_fbus_bulk_rx_reset(&s->bulk);
    finger->data_count = 0;
}

static wsg_finger_type_t finger_type(uint8_t type)
{
    switch (type) {
    case FBUS_TYPE_GENERIC:
        return FINGER_GENERIC;
    case FBUS_TYPE_FMF:
        return FINGER_FMF;
    case FBUS_TYPE_DSA:
        return FINGER_DSA;
    default:
        return FINGER_NONE;
    }
}

static void on_heartbeat(fbus_slot_t *s, wsg_finger_t *finger, const fbus_heartbeat_t *hb)
{
    if (hb->state == FBUS_NODE_BOOT && s->config) {
        forget_node(s, finger);
    }
    s->node_state = hb->state;
    if (hb->faults != s->node_faults) {
        s->node_faults = hb->faults;
        s->unpublished = true;
    }
    if (hb->state != FBUS_NODE_OPERATIONAL) {
        finger->data_count = 0;
    }
}

static void on_descriptor(fbus_slot_t *s, wsg_finger_t *finger, const fbus_descriptor_t *d)
{
    unsigned values = (unsigned)d->rows * d->cols;
    bool usable = d->version == FBUS_PROTO_VERSION && values <= WSG_FINGER_DATA_MAX &&
                  finger_type(d->type) != FINGER_NONE;
    if (!usable) {
        return; /* FF_CONFIG_AVAIL stays off */
    }
    if (s->config && memcmp(&s->desc, d, sizeof(*d)) != 0) {
        finger->data_count = 0;
    }
    s->desc = *d;
    s->config = true;
    s->unpublished = true;
}

static void on_measure(fbus_slot_t *s, wsg_finger_t *finger, const fbus_measure_t *m)
{
    if (!s->config || s->desc.encoding != FBUS_ENC_MEASURE ||
        s->node_state != FBUS_NODE_OPERATIONAL) {
        return;
    }
    finger->data[0] = (float)m->value_milli / 1000.0f;
    finger->data_count = 1;
    s->tare_count = m->tare_count;
    if (s->tare_pending && m->tare_count != s->tare_count_before) {
        s->tare_pending = false; /* the node counted it: this value is tared */
    }
}

/* A completed transfer becomes the finger's data. */
static void on_transfer(fbus_slot_t *s, wsg_finger_t *finger)
{
    unsigned values = (unsigned)s->desc.rows * s->desc.cols;
    if (s->bulk.count < values) {
        return; /* a short transfer: keep the previous data */
    }
    unsigned i = 0;
    for (; i + 4u <= values; i += 4u) { /* four at a time: the compiler may use vectors */
        finger->data[i] = (float)s->bulk.values[i];
        finger->data[i + 1u] = (float)s->bulk.values[i + 1u];
        finger->data[i + 2u] = (float)s->bulk.values[i + 2u];
        finger->data[i + 3u] = (float)s->bulk.values[i + 3u];
    }
    for (; i < values; i++) {
        finger->data[i] = (float)s->bulk.values[i];
    }
    finger->data_count = (uint16_t)values;
}

/* How many frames from f on have f's identifier. */
static unsigned run_length(const hal_can_frame_t *f, unsigned n)
{
    unsigned run = 1;
    while (run < n && f[run].id == f->id) {
        run++;
    }
    return run;
}

/* Segments go from the frames straight into the transfer: the run of
 * frames from f on with f's identifier (nothing in it changes what is
 * checked here), found as they are fed. Returns its length. */
static unsigned on_bulk(fbus_slot_t *s, wsg_finger_t *finger, const hal_can_frame_t *f, unsigned n)
{
    if (!s->config || s->desc.encoding != FBUS_ENC_BULK || s->node_state != FBUS_NODE_OPERATIONAL) {
        return run_length(f, n);
    }
    unsigned taken = 0;
    do {
        bool done = false;
        taken += wsg_fbus_bulk_rx_feed_frames(&s->bulk, &f[taken], n - taken, &done);
        if (done) {
            on_transfer(s, finger);
        }
    } while (taken < n && f[taken].id == f->id);
    return taken;
}

/* Takes f[0], with the frames after it that go in the same go (a run of
 * BULK frames of one node): returns how many. The frame's function code
 * says which type it is: one unpack, not a try of each. */
static unsigned dispatch_frames(fbus_slot_t *s, wsg_finger_t *finger, const hal_can_frame_t *f,
                                unsigned n)
{
    fbus_heartbeat_t hb;
    fbus_descriptor_t d;
    fbus_measure_t m;
    switch (fbus_func_of(f->id)) {
    case FBUS_ID_HEARTBEAT:
        if (wsg_fbus_unpack_heartbeat(f, &hb)) {
            on_heartbeat(s, finger, &hb);
        }
        break;
    case FBUS_ID_DESCRIPTOR:
        if (wsg_fbus_unpack_descriptor(f, &d)) {
            on_descriptor(s, finger, &d);
        }
        break;
    case FBUS_ID_MEASURE:
        if (wsg_fbus_unpack_measure(f, &m)) {
            on_measure(s, finger, &m);
        }
        break;
    case FBUS_ID_BULK:
        return on_bulk(s, finger, f, n);
    default:
        break;
    }
    return 1;
}

/* Takes the first frame of f[0..n), with those after it that are taken in
 * the same go: returns how many. */
static unsigned take_frames(finger_bus_t *bus, wsg_fingers_t *fingers, const hal_can_frame_t *f,
                            unsigned n, uint64_t now_us)
{
    uint8_t injected;
    if (fbus_func_of(f->id) == FBUS_ID_SIMCTL && wsg_fbus_unpack_simctl(f, &injected)) {
        bus->wake = true; /* only an on-demand bus passes it */
        return 1;
    }
    int slot = wsg_fbus_slot_of_node(fbus_node_of(f->id));
    if (slot < 0 || (bus->power_mask & (1u << slot)) == 0u) {
        return 1;
    }
    fbus_slot_t *s = &bus->slot[slot];
    if (s->comm_fault) {
        slot_log(HAL_LOG_INFO, (unsigned)slot, "communication restored");
    }
    if (!s->heard || s->comm_fault) {
        s->unpublished = true;
    }
    s->heard = true;
    s->comm_fault = false;
    s->last_rx_us = now_us;
    return dispatch_frames(s, &fingers->slot[slot], f, n);
}

/* Takes frames[0..count), the first poll's, and all that follow. The bus
 * was polled at this instant already: a poll its quiet time says finds
 * nothing changes nothing, and is not made. */
static void receive_all(finger_bus_t *bus, wsg_fingers_t *fingers, const hal_can_frame_t *frames,
                        unsigned count, uint64_t now_us)
{
    hal_can_frame_t one;
    while (frames != NULL) {
        for (unsigned i = 0; i < count;) {
            i += take_frames(bus, fingers, &frames[i], count - i, now_us);
        }
        frames =
            now_us < *bus->bus_quiet_until_us ? NULL : hal_can_recv_many(bus->can, &one, &count);
    }
}

static void supervise(finger_bus_t *bus, unsigned slot, wsg_finger_t *finger, uint64_t now_us)
{
    fbus_slot_t *s = &bus->slot[slot];
    if (!s->heard || s->comm_fault) {
        return;
    }
    if (now_us - s->last_rx_us > FBUS_COMM_TIMEOUT_US) {
        s->comm_fault = true;
        s->unpublished = true;
        s->tare_pending = false;
        finger->data_count = 0;
        wsg_fbus_bulk_rx_reset(&s->bulk);
        bus->comm_faults++;
        slot_log(HAL_LOG_WARN, slot, "communication fault (no frame within the timeout)");
        return;
    }
    bool waiting = !s->config && s->node_state == FBUS_NODE_OPERATIONAL;
    if (waiting && now_us - s->desc_request_us >= FBUS_DESCRIPTOR_RETRY_US) {
        hal_can_frame_t f;
        wsg_fbus_pack_command(&f, FBUS_NODE_ID(slot), FBUS_CMD_REQ_DESCRIPTOR);
        send(bus, &f);
        s->desc_request_us = now_us;
    }
    if (s->tare_pending && s->tare_sent_us == FBUS_TARE_UNSTAMPED) {
        s->tare_sent_us = now_us; /* sent between two steps: the wait starts now */
    } else if (s->tare_pending && now_us - s->tare_sent_us >= FBUS_TARE_RETRY_US) {
        repeat_tare(bus, slot, now_us);
    }
}

/* The slot as FTYPE and FFLAGS show it (Appendix C), when what they
 * follow changed (unpublished): the slot's heard, comm_fault, config,
 * desc.type and node_faults, which set unpublished where they change, and
 * its power (set once, at init). Nothing else writes the finger's flags
 * and type. */
static void publish(finger_bus_t *bus, unsigned slot, wsg_finger_t *finger)
{
    fbus_slot_t *s = &bus->slot[slot];
    if (!s->unpublished) {
        return;
    }
    s->unpublished = false;
    uint16_t flags = 0;
    if ((bus->power_mask & (1u << slot)) != 0u && s->heard) {
        flags |= (uint16_t)WSG_FLAG(FF_POWER_ON);
    }
    if (s->config) {
        flags |= (uint16_t)WSG_FLAG(FF_CONFIG_AVAIL);
    }
    if (s->heard && !s->comm_fault) {
        flags |= (uint16_t)WSG_FLAG(FF_COMM_OPEN);
    }
    if ((s->node_faults & FBUS_FAULT_POWER) != 0u) {
        flags |= (uint16_t)WSG_FLAG(FF_POWER_FAULT);
    }
    if (s->comm_fault) {
        flags |= (uint16_t)WSG_FLAG(FF_COMM_FAULT);
    }
    if ((s->node_faults & FBUS_FAULT_INIT) != 0u) {
        flags |= (uint16_t)WSG_FLAG(FF_INIT_FAULT);
    }
    wsg_finger_type_t type = s->config ? finger_type(s->desc.type) : FINGER_NONE;
    if (flags != finger->flags || type != finger->type) {
        bus->wake = true;
    }
    finger->flags = flags;
    finger->type = type;
}

static void broadcast_state(finger_bus_t *bus, const fbus_input_t *in)
{
    fbus_state_t st = {in->position_mm, in->motor_force_n, bus->power_mask, in->grip_state,
                       bus->counter++};
    hal_can_frame_t f;
    wsg_fbus_pack_state(&f, &st);
    send(bus, &f);
    bus->next_state_us += FBUS_STATE_PERIOD_US;
    if (bus->next_state_us <= in->now_us) {
        bus->next_state_us = in->now_us + FBUS_STATE_PERIOD_US;
    }
}

static float clampf(float v, float lo, float hi)
{
    return v < lo ? lo : (v > hi ? hi : v);
}

static float absf(float v)
{
    return v < 0.0f ? -v : v;
}

static void request_force(finger_bus_t *bus, float limit_n)
{
    bus->limit_n = limit_n;
    bus->force_request = true;
}

/* While a part is held, integrates the FMF's error into a trim of the
 * motor's force limit so that the measured force reaches the grip force. */
static void regulate(finger_bus_t *bus, const wsg_fingers_t *fingers, const fbus_input_t *in)
{
    bool on = wsg_fingers_force_control(fingers) && in->holding;
    if (!on) {
        if (bus->regulating && in->holding) {
            request_force(bus, in->grip_force_n); /* the FMF went away: the motor's estimate */
        }
        bus->regulating = false;
        bus->trim_n = 0.0f;
        return;
    }
    float target = in->grip_force_n;
    float dt = bus->regulating ? (float)(in->now_us - bus->regulated_us) * 1e-6f : 0.0f;
    if (!bus->regulating) {
        bus->limit_n = target;
    }
    bus->regulating = true;
    bus->regulated_us = in->now_us;
    float error = target - wsg_fingers_measured_force(fingers);
    float span = FBUS_FORCE_TRIM_SHARE * target;
    bus->trim_n = clampf(bus->trim_n + FBUS_FORCE_KI_PER_S * error * dt, -span, span);
    float limit = clampf(target + bus->trim_n, 0.0f, in->force_max_n);
    if (absf(limit - bus->limit_n) >= 0.005f) {
        request_force(bus, limit);
    }
}

void wsg_finger_bus_wake_for_force(finger_bus_t *bus, float force_n)
{
    bus->woke_force_n = force_n;
    bus->wake = true;
    note_deadline(bus);
}

bool wsg_finger_bus_take_force_request(finger_bus_t *bus, float *limit_n)
{
    if (!bus->force_request) {
        return false;
    }
    bus->force_request = false;
    *limit_n = bus->limit_n;
    return true;
}

static uint64_t earliest(uint64_t a, uint64_t b)
{
    return a < b ? a : b;
}

/* The first instant supervise() can act on the slot without a frame
 * arriving first (UINT64_MAX: only a frame changes it). */
static uint64_t supervise_due_us(const fbus_slot_t *s)
{
    if (!s->heard || s->comm_fault) {
        return UINT64_MAX;
    }
    uint64_t due = s->last_rx_us + FBUS_COMM_TIMEOUT_US + 1u;
    if (!s->config && s->node_state == FBUS_NODE_OPERATIONAL) {
        due = earliest(due, s->desc_request_us + FBUS_DESCRIPTOR_RETRY_US);
    }
    if (s->tare_pending) {
        due = earliest(due, s->tare_sent_us == FBUS_TARE_UNSTAMPED
                                ? 0u
                                : s->tare_sent_us + FBUS_TARE_RETRY_US);
    }
    return due;
}

/* After a full step: never quiet on a real bus or while the force loop
 * runs (a full step leaves wake clear). */
static void note_quiet_until(finger_bus_t *bus)
{
    if (!bus->can->ops->on_demand || bus->regulating) {
        bus->quiet_until_us = 0;
        return;
    }
    uint64_t until = bus->next_state_us;
    for (unsigned i = 0; i < FBUS_SLOTS; i++) {
        until = earliest(until, supervise_due_us(&bus->slot[i]));
    }
    bus->quiet_until_us = until;
}

void wsg_finger_bus_step_full(finger_bus_t *bus, wsg_fingers_t *fingers, const fbus_input_t *in,
                              const hal_can_frame_t *frames, unsigned count)
{
    receive_all(bus, fingers, frames, count, in->now_us);
    for (unsigned i = 0; i < FBUS_SLOTS; i++) {
        supervise(bus, i, &fingers->slot[i], in->now_us);
        publish(bus, i, &fingers->slot[i]);
    }
    regulate(bus, fingers, in);
    if (bus->wake) {
        bus->wake = false;
        bus->awake_until_us = in->now_us + FBUS_SETTLE_US;
    }
    note_quiet_until(bus);
    note_deadline(bus);
}

bool wsg_finger_bus_step(finger_bus_t *bus, wsg_fingers_t *fingers, const fbus_input_t *in)
{
    if (bus->can == NULL || wsg_finger_bus_skip_step(bus, fingers, in->now_us, in->holding)) {
        return false;
    }
    if (in->now_us >= bus->next_state_us) {
        broadcast_state(bus, in); /* first: the supply reaches the fingers before polling */
    }
    bool quiet = wsg_finger_bus_quiet(bus, fingers, in->now_us, in->holding);
    if (bus->unpolled_us != 0u) {
        hal_can_polls_skipped(bus->can, bus->unpolled_us);
        bus->unpolled_us = 0;
    }
    hal_can_frame_t one;
    unsigned count;
    const hal_can_frame_t *frames = hal_can_recv_many(bus->can, &one, &count);
    if (frames == NULL && quiet) {
        return false;
    }
    wsg_finger_bus_step_full(bus, fingers, in, frames, count);
    return true;
}

wsg_status_t wsg_finger_bus_tare(finger_bus_t *bus, wsg_fingers_t *fingers, int index)
{
    wsg_status_t status = wsg_fingers_tare(fingers, index);
    if (status != E_SUCCESS || bus->can == NULL) {
        return status;
    }
    for (int i = 0; i < (int)FBUS_SLOTS; i++) {
        const wsg_finger_t *finger = &fingers->slot[i];
        if ((index < 0 || index == i) && finger->type == FINGER_FMF &&
            wsg_finger_has_data(finger)) {
            fbus_slot_t *s = &bus->slot[i];
            s->tare_pending = true;
            s->tare_sends = 0;
            s->tare_count_before = s->tare_count;
            send_tare(bus, (unsigned)i, FBUS_TARE_UNSTAMPED);
        }
    }
    return E_SUCCESS;
}
