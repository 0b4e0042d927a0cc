/* SPDX-License-Identifier: BSD-3-Clause */
/* The host's finger bus (finger_bus_host.h). */
#include "finger_bus_host.h"

#include <poll.h>
#include <stdio.h>
#include <string.h>

#include "can_loopback.h"
#include "can_socketcan.h"
#include "fleet.h"
#include "gripper.h"
#include "wsg/finger_proto.h"
#include "log.h"
#include "loop.h"

static can_socketcan_t sock;
static const hal_can_t *active_bus;
static char description[64];
static uint8_t injected[FBUS_SLOTS];

static void on_readable(void *ctx, int fd, short revents)
{
    host_loop_t *loop = ctx;
    can_socketcan_drain(&sock);
    if ((revents & (POLLERR | POLLHUP | POLLNVAL)) != 0) {
        host_logf(HAL_LOG_ERROR, "finger bus: CAN socket error (%s); no longer watching it",
                  strerror(-sock.last_error));
        loop_unwatch(loop, fd);
    }
}

static bool start_socketcan(host_loop_t *loop, const char *iface)
{
    char err[160];
    if (!can_socketcan_open(&sock, iface, err, sizeof(err))) {
        host_logf(HAL_LOG_ERROR, "finger bus: %s", err);
        return false;
    }
    if (!loop_watch(loop, can_socketcan_fd(&sock), POLLIN, on_readable, loop)) {
        host_logf(HAL_LOG_ERROR, "finger bus: too many watched descriptors");
        can_socketcan_close(&sock);
        return false;
    }
    active_bus = can_socketcan_bus(&sock);
    snprintf(description, sizeof(description), "SocketCAN %s", iface);
    return true;
}

bool finger_bus_host_start(host_loop_t *loop, const host_options_t *opts)
{
    memset(injected, 0, sizeof(injected));
    sock.fd = -1;
    if (opts->can_iface != NULL) {
        if (!start_socketcan(loop, opts->can_iface)) {
            return false;
        }
    } else {
        fbus_type_t types[FBUS_SLOTS];
        finger_node_params_t params;
        wsg_finger_node_defaults(&params);
        if (!wsg_finger_node_parse_pair(opts->fingers, types)) {
            host_logf(HAL_LOG_ERROR, "finger bus: bad finger list '%s'", opts->fingers);
            return false;
        }
        if (types[0] == FBUS_TYPE_NONE && types[1] == FBUS_TYPE_NONE) {
            /* no finger on it: no bus, so an idle device has nothing to do */
            active_bus = NULL;
            snprintf(description, sizeof(description), "none (no fingers)");
            return true;
        }
        can_loopback_init(types, &params);
        active_bus = can_loopback_bus();
        snprintf(description, sizeof(description), "loopback bus (%s)", opts->fingers);
    }
    return true; /* main logs the description after the ready line */
}

void finger_bus_host_stop(host_loop_t *loop)
{
    if (sock.fd >= 0) {
        loop_unwatch(loop, sock.fd);
        can_socketcan_close(&sock);
    }
    active_bus = NULL;
}

const hal_can_t *finger_bus_host_can(void)
{
    return active_bus;
}

const char *finger_bus_host_describe(void)
{
    return description;
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

bool finger_bus_host_inject(unsigned slot, finger_fault_t fault, bool active)
{
    if (slot >= FBUS_SLOTS || active_bus == NULL) {
        return false;
    }
    uint8_t bit = fault_bit(fault);
    injected[slot] = active ? (uint8_t)(injected[slot] | bit) : (uint8_t)(injected[slot] & ~bit);
    hal_can_frame_t f;
    wsg_fbus_pack_simctl(&f, FBUS_NODE_ID(slot), injected[slot]);
    host_logf(HAL_LOG_INFO, "finger %u: fault injection now 0x%02x", slot, injected[slot]);
    if (sock.fd >= 0) {
        return hal_can_send(active_bus, &f);
    }
    /* The in-process bus runs only when the device steps: bring it up to
     * this instant first (what the finger sent until now), then let the
     * device see the injection and watch it take effect. */
    gripper_step_now(fleet_gripper(0));
    bool sent = hal_can_send(active_bus, &f);
    gripper_step_now(fleet_gripper(0));
    return sent;
}
