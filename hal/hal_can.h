/* SPDX-License-Identifier: BSD-3-Clause */
/* A classic CAN 2.0 controller: send a frame, poll received frames, set
 * acceptance filters. A port hands the core a hal_can_t; the core never sees
 * the driver behind it (SocketCAN, an in-process bus, a microcontroller's
 * CAN peripheral). */
#ifndef HAL_CAN_H
#define HAL_CAN_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#define HAL_CAN_MAX_DLC 8u
#define HAL_CAN_STD_ID_MASK 0x7FFu
#define HAL_CAN_EXT_ID_MASK 0x1FFFFFFFu
#define HAL_CAN_MAX_FILTERS 8u

#define HAL_CAN_FLAG_EXT 0x01u /* 29-bit identifier */
#define HAL_CAN_FLAG_RTR 0x02u /* remote request */

typedef struct {
    uint32_t id;
    uint8_t dlc; /* 0..8 */
    uint8_t flags;
    uint8_t data[HAL_CAN_MAX_DLC];
} hal_can_frame_t;

/* Accepts a frame when (frame.id & mask) == (id & mask) and the frame's
 * EXT flag equals the filter's. */
typedef struct {
    uint32_t id;
    uint32_t mask;
    uint8_t flags;
} hal_can_filter_t;

typedef struct {
    /* Queues one frame; false when the controller cannot take it now. */
    bool (*send)(void *ctx, const hal_can_frame_t *frame);
    /* Takes the oldest received frame; false when none is waiting. */
    bool (*recv)(void *ctx, hal_can_frame_t *frame);
    /* Replaces the acceptance filters; count 0 accepts every frame. */
    bool (*set_filters)(void *ctx, const hal_can_filter_t *filters, unsigned count);
    /* True when the nodes on this bus run only when the controller polls it
     * (an in-process simulation): nothing happens on the bus between two
     * polls, so the controller need not poll on a timer while nothing
     * changes. False for a real bus. */
    bool on_demand;
    /* Optional (NULL: recv only): takes every frame waiting at once, in the
     * controller's own storage: the oldest, *count (at least 1) of them in
     * a row, valid until the next call of an operation on this controller;
     * NULL when none is waiting. Saves a call and a copy per frame on a bus
     * whose frames come in bursts (a DSA's 28-frame transfer). */
    const hal_can_frame_t *(*recv_many)(void *ctx, unsigned *count);
    /* Optional (NULL: send, frame by frame): sends frames[0..count) in
     * order, each as send() would; returns how many were taken. Saves a
     * call per frame of a burst. */
    unsigned (*send_many)(void *ctx, const hal_can_frame_t *frames, unsigned count);
    /* Optional, on an on-demand bus (NULL: every poll is made): where the
     * bus keeps the instant before which a poll would find nothing and
     * change nothing but the time the bus was last polled at. The bus's own
     * operations keep it current, so the controller reads it (no call) and
     * may skip such polls, as long as it tells the bus the time of the last
     * one it skipped with polls_skipped() before it polls again. Saves a
     * call per control step while the nodes have nothing to do. */
    const uint64_t *(*quiet_until_us)(void *ctx);
    void (*polls_skipped)(void *ctx, uint64_t last_us);
} hal_can_ops_t;

/* A bus: the driver's operations and its instance (the shape of every HAL
 * handle). ops NULL: no bus. */
typedef struct {
    const hal_can_ops_t *ops;
    void *ctx;
} hal_can_t;

static inline bool hal_can_send(const hal_can_t *can, const hal_can_frame_t *frame)
{
    return can->ops->send(can->ctx, frame);
}

/* Sends frames[0..count) in order; returns how many were taken. */
static inline unsigned hal_can_send_many(const hal_can_t *can, const hal_can_frame_t *frames,
                                         unsigned count)
{
    if (can->ops->send_many != NULL) {
        return can->ops->send_many(can->ctx, frames, count);
    }
    unsigned sent = 0;
    for (unsigned i = 0; i < count; i++) {
        sent += can->ops->send(can->ctx, &frames[i]) ? 1u : 0u;
    }
    return sent;
}

static inline bool hal_can_recv(const hal_can_t *can, hal_can_frame_t *frame)
{
    return can->ops->recv(can->ctx, frame);
}

/* Takes the frames waiting: all at once where the controller can hand them
 * out in place (recv_many), else one, into *one. NULL when none is waiting;
 * else *count frames, valid until the next call on the controller. */
static inline const hal_can_frame_t *hal_can_recv_many(const hal_can_t *can, hal_can_frame_t *one,
                                                       unsigned *count)
{
    if (can->ops->recv_many != NULL) {
        return can->ops->recv_many(can->ctx, count);
    }
    *count = 1;
    return can->ops->recv(can->ctx, one) ? one : NULL;
}

/* Where the bus keeps the end of its quiet time (quiet_until_us): a
 * controller skips no poll on a bus without one (its own zero). */
static inline const uint64_t *hal_can_quiet_until_us(const hal_can_t *can, const uint64_t *none)
{
    return can->ops->quiet_until_us != NULL ? can->ops->quiet_until_us(can->ctx) : none;
}

/* For a bus with quiet_until_us only. */
static inline void hal_can_polls_skipped(const hal_can_t *can, uint64_t last_us)
{
    can->ops->polls_skipped(can->ctx, last_us);
}

static inline bool hal_can_set_filters(const hal_can_t *can, const hal_can_filter_t *filters,
                                       unsigned count)
{
    return can->ops->set_filters(can->ctx, filters, count);
}

/* The software form of the filters, for drivers without hardware filtering. */
static inline bool hal_can_filters_accept(const hal_can_filter_t *filters, unsigned count,
                                          const hal_can_frame_t *frame)
{
    if (count == 0u) {
        return true;
    }
    for (unsigned i = 0; i < count; i++) {
        const hal_can_filter_t *f = &filters[i];
        bool ext = (frame->flags & HAL_CAN_FLAG_EXT) != 0u;
        bool want_ext = (f->flags & HAL_CAN_FLAG_EXT) != 0u;
        if (ext == want_ext && (frame->id & f->mask) == (f->id & f->mask)) {
            return true;
        }
    }
    return false;
}

#endif
