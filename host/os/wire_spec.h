/* SPDX-License-Identifier: BSD-3-Clause */
/* Wire conditions (docs/network.md): how the network between a client and
 * the device behaves, as text (`--net`, `[net] conditions`, the control
 * channel's NET) and as the figures the servers apply (host/port/wire.c).
 * A rule on text alone, below both the configuration that checks it and
 * the servers that apply it; and the seeded generator every random choice
 * of the conditions comes from. */
#ifndef HOST_OS_WIRE_SPEC_H
#define HOST_OS_WIRE_SPEC_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

/* Limits of the figures (docs/network.md lists them). */
#define WIRE_SPLIT_MAX 16u         /* writes one message may leave in */
#define WIRE_TIME_MAX_US 10000000u /* latency, jitter, gaps, coalescing window: 10 s */
#define WIRE_RESET_MAX_US 3600000000u
/* Text of a spec as wire_spec_format() writes it, with its NUL. */
#define WIRE_SPEC_TEXT_MAX 192

typedef struct {
    /* TCP, what the device sends */
    uint32_t split;      /* a message leaves in 2..split writes; 0: whole */
    uint32_t gap_min_us; /* between the writes of a split message */
    uint32_t gap_max_us;
    uint32_t coalesce_us; /* messages due in one window of this length leave
                             in one write; 0: each its own write */
    uint64_t reset_us;    /* a reset (RST) at a random instant within this
                             after the connection opens; 0: never */
    /* both transports, what the device sends */
    uint32_t latency_us;
    uint32_t jitter_us; /* added to the latency: uniform in [0, jitter] */
    /* UDP: probabilities per datagram, 0..1 */
    double loss;    /* both ways */
    double dup;     /* both ways */
    double reorder; /* what the device sends: held back behind the next */
    uint64_t seed;  /* of every random choice (with the session's stream) */
    bool seed_set;  /* seed= named it: it wins over the run's --seed */
} wire_spec_t;

/* No condition: the wire is ideal. */
void wire_spec_off(wire_spec_t *spec);
/* True when the spec changes anything on the wire. */
bool wire_spec_active(const wire_spec_t *spec);
/* Applies text to spec: comma-separated items, a preset name (off, rough,
 * split, lossy, slow; only as the first item: it sets every figure first)
 * and KEY=VALUE items (split=N, gap=MS[-MS], coalesce=MS, latency=MS,
 * jitter=MS, reset=MS, loss=P, dup=P, reorder=P, seed=N: without it the
 * wires draw from the run's --seed, host/port/wire.c). On error spec is
 * unchanged and why (cap bytes) says what is wrong; false. */
bool wire_spec_parse(wire_spec_t *spec, const char *text, char *why, size_t cap);
/* The spec as text wire_spec_parse() reads back to the same figures:
 * "off" or its non-zero items, "split=4,gap=0.5-3,...". */
void wire_spec_format(const wire_spec_t *spec, char *out, size_t cap);

/* The seeded generator (splitmix64): one stream per session, derived from
 * the run's seed and the session's number, so a run gives the same choices
 * whatever else happens between sessions. */
typedef struct {
    uint64_t state;
} wire_rng_t;

void wire_rng_seed(wire_rng_t *rng, uint64_t seed, uint64_t stream);
uint64_t wire_rng_next(wire_rng_t *rng);
/* Uniform in [0, 1). */
double wire_rng_unit(wire_rng_t *rng);
/* Uniform in [lo, hi] (lo <= hi). */
uint64_t wire_rng_range(wire_rng_t *rng, uint64_t lo, uint64_t hi);

#endif
