/* SPDX-License-Identifier: BSD-3-Clause */
/* hal_can_t over SocketCAN (can_socketcan.h). */
#include "can_socketcan.h"

#include <string.h>

#include "can_socketcan_adapt.h"

static bool sc_send(void *ctx, const hal_can_frame_t *frame)
{
    can_socketcan_t *s = ctx;
    int rc = can_adapt_send(s->fd, frame);
    if (rc < 0) {
        s->tx_errors++;
        s->last_error = rc;
        return false;
    }
    return true;
}

static void push(can_socketcan_t *s, const hal_can_frame_t *frame)
{
    if (s->count == CAN_SOCKETCAN_RING) {
        /* drop the oldest: the newest data matters most */
        s->head = (s->head + 1u) % CAN_SOCKETCAN_RING;
        s->count--;
    }
    s->ring[(s->head + s->count) % CAN_SOCKETCAN_RING] = *frame;
    s->count++;
}

void can_socketcan_drain(can_socketcan_t *s)
{
    hal_can_frame_t frame;
    int rc;
    while ((rc = can_adapt_recv(s->fd, &frame)) > 0) {
        push(s, &frame);
    }
    if (rc < 0) {
        s->last_error = rc;
    }
}

static bool sc_recv(void *ctx, hal_can_frame_t *frame)
{
    can_socketcan_t *s = ctx;
    if (s->count == 0u) {
        can_socketcan_drain(s);
    }
    if (s->count == 0u) {
        return false;
    }
    *frame = s->ring[s->head];
    s->head = (s->head + 1u) % CAN_SOCKETCAN_RING;
    s->count--;
    return true;
}

static bool sc_set_filters(void *ctx, const hal_can_filter_t *filters, unsigned count)
{
    can_socketcan_t *s = ctx;
    int rc = can_adapt_set_filters(s->fd, filters, count);
    if (rc < 0) {
        s->last_error = rc;
    }
    return rc == 0;
}

static const hal_can_ops_t sc_ops = {sc_send, sc_recv, sc_set_filters, false,
                                     NULL,    NULL,    NULL,           NULL};

bool can_socketcan_open(can_socketcan_t *s, const char *ifname, char *err, size_t err_len)
{
    memset(s, 0, sizeof(*s));
    s->fd = can_adapt_open(ifname, err, err_len);
    s->can = (hal_can_t){&sc_ops, s};
    return s->fd >= 0;
}

void can_socketcan_close(can_socketcan_t *s)
{
    can_adapt_close(s->fd);
    s->fd = -1;
}

const hal_can_t *can_socketcan_bus(can_socketcan_t *s)
{
    return &s->can;
}

int can_socketcan_fd(const can_socketcan_t *s)
{
    return s->fd;
}
