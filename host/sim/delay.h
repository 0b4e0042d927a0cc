/* SPDX-License-Identifier: BSD-3-Clause */
/* Injected reply delay: the next reply line of a session, and everything
 * after it, is held back for a while of simulated time, then delivered in
 * order. Works for TCP and UDP alike by standing in for the session's I/O. */
#ifndef SIM_DELAY_H
#define SIM_DELAY_H

#include <stdbool.h>
#include <stdint.h>

#include "wsg/wsg_conn.h"

/* Arms a delay of delay_us for the connection's next reply line. */
void simctl_delay_arm(wsg_conn_t *c, uint32_t delay_us);
/* Delivers what is due at now_us; returns how many sessions were released. */
unsigned simctl_delay_release_due(uint64_t now_us);
/* Earliest pending release, or UINT64_MAX. */
uint64_t simctl_delay_next_us(void);
/* Drops every delay (armed or holding); held lines are delivered first when
 * send is true, otherwise discarded. */
void simctl_delay_clear_all(const wsg_device_t *device, bool send);

typedef struct {
    const wsg_device_t *device;
    uint64_t session_id;
    uint32_t delay_us;
    bool holding;        /* a reply arrived and is being held */
    uint64_t release_us; /* when holding */
    unsigned lines_held;
} simctl_delay_info_t;

/* True while the connection's replies are held back. */
bool simctl_delay_holding(const wsg_conn_t *c);

/* The i-th active delay (0-based); false past the last. */
bool simctl_delay_info(unsigned i, simctl_delay_info_t *out);

#endif
