/* SPDX-License-Identifier: BSD-3-Clause */
/* Packing and unpacking of finger-bus frames (finger_proto.h). */
#include "wsg/finger_proto.h"

static void put_u16(uint8_t *p, uint16_t v)
{
    p[0] = (uint8_t)(v & 0xFFu);
    p[1] = (uint8_t)(v >> 8);
}

static uint16_t get_u16(const uint8_t *p)
{
    return (uint16_t)(p[0] | (p[1] << 8));
}

static void put_u32(uint8_t *p, uint32_t v)
{
    put_u16(p, (uint16_t)(v & 0xFFFFu));
    put_u16(p + 2, (uint16_t)(v >> 16));
}

static uint32_t get_u32(const uint8_t *p)
{
    return (uint32_t)get_u16(p) | ((uint32_t)get_u16(p + 2) << 16);
}

/* A physical value in units of `step`, rounded and clamped to 0..65535. */
static uint16_t to_u16(float value, float step)
{
    float raw = value / step + 0.5f;
    if (!(raw > 0.0f)) {
        return 0;
    }
    return raw >= 65535.0f ? 65535u : (uint16_t)raw;
}

static void begin(hal_can_frame_t *f, uint32_t id, uint8_t dlc)
{
    *f = (hal_can_frame_t){.id = id, .dlc = dlc}; /* two stores, not a memset() call */
}

static bool is(const hal_can_frame_t *f, uint32_t func, uint8_t min_dlc)
{
    return (f->flags & (HAL_CAN_FLAG_EXT | HAL_CAN_FLAG_RTR)) == 0u &&
           fbus_func_of(f->id) == func && f->dlc >= min_dlc;
}

uint32_t wsg_fbus_id(uint32_t func, uint8_t node)
{
    return func + (uint32_t)(node & FBUS_NODE_MASK);
}

void wsg_fbus_pack_state(hal_can_frame_t *f, const fbus_state_t *s)
{
    begin(f, FBUS_ID_STATE, 8);
    put_u16(&f->data[0], to_u16(s->position_mm, 0.01f));
    put_u16(&f->data[2], to_u16(s->force_n, 0.01f));
    f->data[4] = s->power_mask;
    f->data[5] = s->grip_state;
    f->data[6] = s->counter;
}

bool wsg_fbus_unpack_state(const hal_can_frame_t *f, fbus_state_t *s)
{
    if (!is(f, FBUS_ID_STATE, 7) || fbus_node_of(f->id) != 0u) {
        return false;
    }
    s->position_mm = (float)get_u16(&f->data[0]) * 0.01f;
    s->force_n = (float)get_u16(&f->data[2]) * 0.01f;
    s->power_mask = f->data[4];
    s->grip_state = f->data[5];
    s->counter = f->data[6];
    return true;
}

void wsg_fbus_pack_command(hal_can_frame_t *f, uint8_t node, uint8_t command)
{
    begin(f, wsg_fbus_id(FBUS_ID_COMMAND, node), 8);
    f->data[0] = command;
}

bool wsg_fbus_unpack_command(const hal_can_frame_t *f, uint8_t *command)
{
    if (!is(f, FBUS_ID_COMMAND, 1)) {
        return false;
    }
    *command = f->data[0];
    return true;
}

void wsg_fbus_pack_descriptor(hal_can_frame_t *f, uint8_t node, const fbus_descriptor_t *d)
{
    begin(f, wsg_fbus_id(FBUS_ID_DESCRIPTOR, node), 8);
    f->data[0] = d->type;
    f->data[1] = d->version;
    f->data[2] = d->rows;
    f->data[3] = d->cols;
    f->data[4] = d->encoding;
    f->data[5] = d->features;
    put_u16(&f->data[6], d->firmware);
}

bool wsg_fbus_unpack_descriptor(const hal_can_frame_t *f, fbus_descriptor_t *d)
{
    if (!is(f, FBUS_ID_DESCRIPTOR, 8)) {
        return false;
    }
    d->type = f->data[0];
    d->version = f->data[1];
    d->rows = f->data[2];
    d->cols = f->data[3];
    d->encoding = f->data[4];
    d->features = f->data[5];
    d->firmware = get_u16(&f->data[6]);
    return true;
}

void wsg_fbus_pack_measure(hal_can_frame_t *f, uint8_t node, const fbus_measure_t *m)
{
    begin(f, wsg_fbus_id(FBUS_ID_MEASURE, node), 8);
    put_u32(&f->data[0], (uint32_t)m->value_milli);
    f->data[4] = m->counter;
    f->data[5] = m->status;
    f->data[6] = m->tare_count;
}

bool wsg_fbus_unpack_measure(const hal_can_frame_t *f, fbus_measure_t *m)
{
    if (!is(f, FBUS_ID_MEASURE, 7)) {
        return false;
    }
    m->value_milli = (int32_t)get_u32(&f->data[0]);
    m->counter = f->data[4];
    m->status = f->data[5];
    m->tare_count = f->data[6];
    return true;
}

void wsg_fbus_pack_bulk(hal_can_frame_t *f, uint8_t node, const fbus_bulk_t *b)
{
    begin(f, wsg_fbus_id(FBUS_ID_BULK, node), 8);
    f->data[0] = (uint8_t)((b->segment & 0x7Fu) | (b->last ? 0x80u : 0u));
    f->data[1] = b->transfer;
    for (unsigned i = 0; i < FBUS_BULK_VALUES_PER_FRAME; i++) {
        put_u16(&f->data[2 + 2 * i], b->values[i]);
    }
}

void wsg_fbus_bulk_wire(uint8_t *out, const uint16_t *values, unsigned count)
{
    for (unsigned i = 0; i < count; i++) {
        put_u16(&out[2u * i], values[i]);
    }
}

#define BULK_WIRE_BYTES (2u * FBUS_BULK_VALUES_PER_FRAME)

void wsg_fbus_pack_bulk_transfer(hal_can_frame_t *frames, uint8_t node, uint8_t transfer,
                                 const uint8_t *wire, unsigned segments)
{
    uint32_t id = wsg_fbus_id(FBUS_ID_BULK, node);
    for (unsigned s = 0; s < segments; s++) {
        hal_can_frame_t *f = &frames[s];
        begin(f, id, 8);
        f->data[0] = (uint8_t)(s & 0x7Fu);
        f->data[1] = transfer;
        const uint8_t *values = &wire[s * BULK_WIRE_BYTES];
        for (unsigned i = 0; i < BULK_WIRE_BYTES; i++) { /* six stores (no memcpy() call) */
            f->data[2u + i] = values[i];
        }
    }
    if (segments > 0u) {
        frames[segments - 1u].data[0] |= 0x80u; /* the last one */
    }
}

bool wsg_fbus_unpack_bulk(const hal_can_frame_t *f, fbus_bulk_t *b)
{
    if (!is(f, FBUS_ID_BULK, 8)) {
        return false;
    }
    b->segment = f->data[0] & 0x7Fu;
    b->last = (f->data[0] & 0x80u) != 0u;
    b->transfer = f->data[1];
    for (unsigned i = 0; i < FBUS_BULK_VALUES_PER_FRAME; i++) {
        b->values[i] = get_u16(&f->data[2 + 2 * i]);
    }
    return true;
}

void wsg_fbus_pack_heartbeat(hal_can_frame_t *f, uint8_t node, const fbus_heartbeat_t *h)
{
    begin(f, wsg_fbus_id(FBUS_ID_HEARTBEAT, node), 8);
    f->data[0] = h->state;
    f->data[1] = h->faults;
    f->data[2] = h->counter;
}

bool wsg_fbus_unpack_heartbeat(const hal_can_frame_t *f, fbus_heartbeat_t *h)
{
    if (!is(f, FBUS_ID_HEARTBEAT, 3)) {
        return false;
    }
    h->state = f->data[0];
    h->faults = f->data[1];
    h->counter = f->data[2];
    return true;
}

void wsg_fbus_pack_simctl(hal_can_frame_t *f, uint8_t node, uint8_t faults)
{
    begin(f, wsg_fbus_id(FBUS_ID_SIMCTL, node), 8);
    f->data[0] = faults;
}

bool wsg_fbus_unpack_simctl(const hal_can_frame_t *f, uint8_t *faults)
{
    if (!is(f, FBUS_ID_SIMCTL, 1)) {
        return false;
    }
    *faults = f->data[0];
    return true;
}

void wsg_fbus_bulk_rx_reset(fbus_bulk_rx_t *rx)
{
    rx->active = false;
    rx->next_segment = 0;
    rx->count = 0;
}

/* Where a segment's values go in rx, or -1 when the segment spoils the
 * transfer (rx is then reset). */
static int segment_first(fbus_bulk_rx_t *rx, uint8_t segment, uint8_t transfer)
{
    if (segment == 0u) {
        rx->active = true;
        rx->transfer = transfer;
        rx->next_segment = 0;
    }
    unsigned first = (unsigned)segment * FBUS_BULK_VALUES_PER_FRAME;
    if (!rx->active || transfer != rx->transfer || segment != rx->next_segment ||
        first + FBUS_BULK_VALUES_PER_FRAME > FBUS_BULK_MAX_VALUES) {
        wsg_fbus_bulk_rx_reset(rx); /* a lost or foreign segment spoils the transfer */
        return -1;
    }
    rx->next_segment++;
    return (int)first;
}

/* After a segment's values are in: true when it was the last one. */
static bool segment_done(fbus_bulk_rx_t *rx, unsigned first, bool last)
{
    if (!last) {
        return false;
    }
    rx->active = false;
    rx->count = (uint16_t)(first + FBUS_BULK_VALUES_PER_FRAME);
    return true;
}

bool wsg_fbus_bulk_rx_feed(fbus_bulk_rx_t *rx, const fbus_bulk_t *segment)
{
    int first = segment_first(rx, segment->segment, segment->transfer);
    if (first < 0) {
        return false;
    }
    for (unsigned i = 0; i < FBUS_BULK_VALUES_PER_FRAME; i++) {
        rx->values[(unsigned)first + i] = segment->values[i];
    }
    return segment_done(rx, (unsigned)first, segment->last);
}

bool wsg_fbus_is_bulk(const hal_can_frame_t *f)
{
    return is(f, FBUS_ID_BULK, 8);
}

/* wsg_fbus_bulk_rx_feed() of a frame wsg_fbus_is_bulk() accepted, without
 * unpacking it first. */
static bool feed_frame(fbus_bulk_rx_t *rx, const hal_can_frame_t *f)
{
    int first = segment_first(rx, f->data[0] & 0x7Fu, f->data[1]);
    if (first < 0) {
        return false;
    }
    _Static_assert(FBUS_BULK_VALUES_PER_FRAME == 3u, "a BULK frame's values, one by one");
    uint16_t *values = &rx->values[first];
    values[0] = get_u16(&f->data[2]);
    values[1] = get_u16(&f->data[4]);
    values[2] = get_u16(&f->data[6]);
    return segment_done(rx, (unsigned)first, (f->data[0] & 0x80u) != 0u);
}

/* A frame's identifier, DLC, flags and first two data bytes (a BULK
 * frame's segment and transfer) as one number, for one comparison: where
 * they lie in memory in that order, compilers load it in one go. */
static uint64_t frame_head(const hal_can_frame_t *f)
{
    return (uint64_t)f->id | (uint64_t)f->dlc << 32 | (uint64_t)f->flags << 40 |
           (uint64_t)f->data[0] << 48 | (uint64_t)f->data[1] << 56;
}

/* One segment more in frame_head()'s number (the segment never carries
 * into the transfer: it stays below FBUS_BULK_MAX_VALUES / 3) */
#define HEAD_SEGMENT_ONE ((uint64_t)1u << 48)

/* The frames from f[0] on that go on the active transfer as its next
 * segments, but not as its last (all of a DSA's 28 but the first and the
 * last), with the identifier id: what feed_frame() would do with them, in
 * fewer steps. Returns how many. */
static unsigned feed_middle(fbus_bulk_rx_t *rx, uint32_t id, const hal_can_frame_t *f, unsigned n)
{
    if (!rx->active || fbus_func_of(id) != FBUS_ID_BULK) {
        return 0;
    }
    unsigned next = rx->next_segment;
    unsigned room = FBUS_BULK_MAX_VALUES / FBUS_BULK_VALUES_PER_FRAME - next;
    unsigned limit = n < room ? n : room;
    /* The next segment's head (frame_head()): its identifier, DLC 8, no
     * flags, its number and the transfer. A frame that differs in any of
     * them (another DLC or flag included) goes frame by frame, which
     * decides as before. */
    uint64_t expected =
        frame_head(&(hal_can_frame_t){.id = id, .dlc = 8u, .data = {(uint8_t)next, rx->transfer}});
    uint16_t *values = &rx->values[next * FBUS_BULK_VALUES_PER_FRAME];
    unsigned k = 0;
    for (; k < limit; k++, values += FBUS_BULK_VALUES_PER_FRAME, expected += HEAD_SEGMENT_ONE) {
        const hal_can_frame_t *frame = &f[k];
        if (frame_head(frame) != expected) {
            break; /* anything else: frame by frame */
        }
        values[0] = get_u16(&frame->data[2]);
        values[1] = get_u16(&frame->data[4]);
        values[2] = get_u16(&frame->data[6]);
    }
    rx->next_segment = (uint8_t)(next + k);
    return k;
}

unsigned wsg_fbus_bulk_rx_feed_frames(fbus_bulk_rx_t *rx, const hal_can_frame_t *f, unsigned n,
                                      bool *done)
{
    uint32_t id = n > 0u ? f[0].id : 0u;
    unsigned i = 0;
    while (i < n && f[i].id == id) {
        i += feed_middle(rx, id, &f[i], n - i);
        if (i == n || f[i].id != id) {
            break;
        }
        if (wsg_fbus_is_bulk(&f[i]) && feed_frame(rx, &f[i])) {
            *done = true;
            return i + 1u;
        }
        i++;
    }
    *done = false;
    return i;
}
