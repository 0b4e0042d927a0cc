/* SPDX-License-Identifier: BSD-3-Clause */
/* A device's finger bus (finger_bus_host.h). */
#include "finger_bus_host.h"

#include <poll.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "wsg/finger_proto.h"
#include "log.h"
#include "loop.h"

static void on_readable(void *ctx, int fd, short revents)
{
    finger_bus_host_t *b = ctx;
    can_socketcan_drain(b->sock);
    if ((revents & (POLLERR | POLLHUP | POLLNVAL)) != 0) {
        host_logf(HAL_LOG_ERROR, "finger bus: CAN socket error (%s); no longer watching it",
                  strerror(-b->sock->last_error));
        loop_unwatch(b->loop, fd);
    }
}

static bool start_socketcan(finger_bus_host_t *b, const char *iface)
{
    char err[160];
    b->sock = malloc(sizeof(*b->sock));
    if (b->sock == NULL) {
        host_logf(HAL_LOG_ERROR, "finger bus: out of memory");
        return false;
    }
    if (!can_socketcan_open(b->sock, iface, err, sizeof(err))) {
        host_logf(HAL_LOG_ERROR, "finger bus: %s", err);
        free(b->sock);
        b->sock = NULL;
        return false;
    }
    if (!loop_watch(b->loop, can_socketcan_fd(b->sock), POLLIN, on_readable, b)) {
        host_logf(HAL_LOG_ERROR, "finger bus: too many watched descriptors");
        can_socketcan_close(b->sock);
        free(b->sock);
        b->sock = NULL;
        return false;
    }
    b->iface = iface;
    return true;
}

static bool start_loopback(finger_bus_host_t *b, const char *fingers)
{
    fbus_type_t types[FBUS_SLOTS];
    finger_node_params_t params;
    wsg_finger_node_defaults(&params);
    if (!wsg_finger_node_parse_pair(fingers, types)) {
        host_logf(HAL_LOG_ERROR, "finger bus: bad finger list '%s'", fingers);
        return false;
    }
    if (types[0] == FBUS_TYPE_NONE && types[1] == FBUS_TYPE_NONE) {
        return true; /* no finger on it: no bus, so an idle device has nothing to do */
    }
    b->loopback = can_loopback_create(types, &params);
    if (b->loopback == NULL) {
        host_logf(HAL_LOG_ERROR, "finger bus: out of memory");
        return false;
    }
    return true;
}

bool finger_bus_host_start(finger_bus_host_t *b, host_loop_t *loop, const char *can_iface,
                           const char *fingers)
{
    memset(b, 0, sizeof(*b));
    b->loop = loop;
    b->fingers = fingers;
    return can_iface != NULL ? start_socketcan(b, can_iface) : start_loopback(b, fingers);
}

void finger_bus_host_stop(finger_bus_host_t *b)
{
    if (b->sock != NULL) {
        loop_unwatch(b->loop, b->sock->fd);
        can_socketcan_close(b->sock);
        free(b->sock);
        b->sock = NULL;
    }
    can_loopback_destroy(b->loopback);
    b->loopback = NULL;
}

const hal_can_t *finger_bus_host_can(const finger_bus_host_t *b)
{
    if (b->sock != NULL) {
        return can_socketcan_bus(b->sock);
    }
    return b->loopback != NULL ? can_loopback_bus(b->loopback) : NULL;
}

can_loopback_t *finger_bus_host_loopback(finger_bus_host_t *b)
{
    return b->loopback;
}

void finger_bus_host_describe(const finger_bus_host_t *b, char *out, size_t cap)
{
    if (b->sock != NULL) {
        snprintf(out, cap, "SocketCAN %s", b->iface);
    } else if (b->loopback != NULL) {
        snprintf(out, cap, "loopback bus (%s)", b->fingers);
    } else {
        snprintf(out, cap, "none (no fingers)");
    }
}

static uint8_t fault_bit(finger_fault_t fault)
{
    switch (fault) {
    case FINGER_FAULT_POWER:
        return FBUS_FAULT_POWER;
    case FINGER_FAULT_INIT:
        return FBUS_FAULT_INIT;
    case FINGER_FAULT_UNPLUG:
    default:
        return FBUS_FAULT_UNPLUG;
    }
}

bool finger_bus_host_inject(finger_bus_host_t *b, unsigned slot, finger_fault_t fault, bool active)
{
    const hal_can_t *can = finger_bus_host_can(b);
    if (slot >= FBUS_SLOTS || can == NULL) {
        return false;
    }
    uint8_t bit = fault_bit(fault);
    b->injected[slot] =
        active ? (uint8_t)(b->injected[slot] | bit) : (uint8_t)(b->injected[slot] & ~bit);
    hal_can_frame_t f;
    wsg_fbus_pack_simctl(&f, FBUS_NODE_ID(slot), b->injected[slot]);
    host_logf(HAL_LOG_INFO, "finger %u: fault injection now 0x%02x", slot, b->injected[slot]);
    return hal_can_send(can, &f);
}
