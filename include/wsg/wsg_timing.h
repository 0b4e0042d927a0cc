/* SPDX-License-Identifier: BSD-3-Clause */
/* The device's pace (docs/timing.md): its command processor and the
 * seeded generator its jitter comes from. The generator is public: the
 * port derives its own seeded streams with it (wire conditions), so one
 * seed makes a whole run reproducible. */
#ifndef WSG_TIMING_H
#define WSG_TIMING_H

#include <stdbool.h>
#include <stdint.h>

#include "wsg_config.h"
#include "wsg_conn.h"

/* splitmix64 (Steele, Lea, Flood 2014): one 64-bit word of state, every
 * seed a full-period stream; small enough for the device's state. */
static inline uint64_t wsg_rand_next(uint64_t *state)
{
    uint64_t z = (*state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

/* The state of stream `index` of a run seeded with `seed`: device i's
 * jitter is stream i; other users take indexes of their own. */
static inline uint64_t wsg_rand_stream(uint64_t seed, uint64_t index)
{
    uint64_t s = seed ^ (index * 0xD1B54A32D192ED03ull);
    return wsg_rand_next(&s);
}

/* A draw uniform on [mean - spread, mean + spread] (µs), never below 0. */
uint32_t wsg_rand_service_us(uint64_t *state, wsg_service_time_t t);

/* Sets the device's pace now (the control channel's TIMING=): requests
 * already waiting keep the slot they were given; the generator starts
 * again from timing->seed. */
void wsg_device_set_timing(wsg_device_t *dev, const wsg_timing_t *timing);
const wsg_timing_t *wsg_device_timing(const wsg_device_t *dev);
/* Requests held for the processor, all connections. */
uint32_t wsg_device_requests_waiting(const wsg_device_t *dev);
/* When the processor has served everything given to it so far (µs; in the
 * past when it is idle). */
uint64_t wsg_device_busy_until_us(const wsg_device_t *dev);

/* A connection's requests that waited for the processor, cumulative:
 * behind a request of the same connection (pipelined: its bytes stayed in
 * the receive buffer until the one before was served) and behind another
 * connection's request or stream frames. */
typedef struct {
    uint32_t behind_own;
    uint32_t behind_others;
} wsg_conn_waits_t;

void wsg_conn_waits(const wsg_conn_t *c, wsg_conn_waits_t *waits);
/* True while the connection holds a whole request for the processor: the
 * port keeps every byte after it until the connection's io resume() hook. */
bool wsg_conn_request_waits(const wsg_conn_t *c);

#endif
