/* SPDX-License-Identifier: BSD-3-Clause */
/* The run's seeded streams: --seed (host_options_t.seed) seeds every
 * random choice of a run, and each user draws from a stream of its own,
 * derived from the seed, what it is for and which item it serves (device
 * i, session n), so that adding a device or a user changes no other
 * stream. The generator is the core's (wsg_timing.h: splitmix64). */
#ifndef HOST_RUN_SEED_H
#define HOST_RUN_SEED_H

#include <stdint.h>

#include "wsg/wsg_timing.h"

typedef enum {
    RUN_SEED_TIMING = 1, /* device i's timing jitter (its wsg_timing_t.seed) */
    RUN_SEED_WIRE = 2,   /* wire conditions */
} run_seed_use_t;

/* The state of the stream for `use` and item `index` of a run seeded with
 * `seed`: hand it to wsg_rand_next(). */
static inline uint64_t run_seed_stream(uint32_t seed, run_seed_use_t use, uint64_t index)
{
    return wsg_rand_stream(wsg_rand_stream(seed, (uint64_t)use), index);
}

#endif
