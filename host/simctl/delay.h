/* SPDX-License-Identifier: BSD-3-Clause */
/* Injected reply delay: the next reply line of a session, and everything
 * after it, is held back for a while of simulated time, then delivered in
 * order. Works for TCP and UDP alike by standing in for the session's I/O. */
#ifndef SIM_DELAY_H
#define SIM_DELAY_H

#include <stdbool.h>
#include <stdint.h>

#include "list.h"
#include "wsg/wsg_conn.h"

/* The armed delays of a control channel, in the order they were armed:
 * one allocated per delayed connection; embedded in its owner, all zero
 * when none is armed. */
typedef struct {
    list_t armed; /* of struct simctl_delay */
    unsigned count;
} simctl_delays_t;

/* Arms a delay of delay_us for the connection's next reply line. */
void simctl_delay_arm(simctl_delays_t *ds, wsg_conn_t *c, uint32_t delay_us);
/* Delivers what is due at now_us; returns how many sessions were released. */
unsigned simctl_delay_release_due(simctl_delays_t *ds, uint64_t now_us);
/* Earliest pending release, or UINT64_MAX. */
uint64_t simctl_delay_next_us(const simctl_delays_t *ds);
/* Drops every delay of the device (armed or holding); held lines are
 * delivered first when send is true, otherwise discarded. Returns how many
 * open connections had one. */
unsigned simctl_delay_clear_all(simctl_delays_t *ds, const wsg_device_t *device, bool send);

typedef struct {
    const wsg_device_t *device;
    uint64_t session_id;
    uint32_t delay_us;
    bool holding;        /* a reply arrived and is being held */
    uint64_t release_us; /* when holding */
    unsigned lines_held;
} simctl_delay_info_t;

/* The connection's delay, read from its I/O (no instance needed: the
 * state dump lists a device's delays by its connections); false when it
 * has none. Its replies are held back while out->holding. */
bool simctl_delay_info(const wsg_conn_t *c, simctl_delay_info_t *out);

#endif
