/* SPDX-License-Identifier: BSD-3-Clause */
#include "wire_spec.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#define ITEM_MAX 64 /* one KEY=VALUE item */

/* The presets (docs/network.md says what each stands for). rough: what a
 * robust driver must survive on any real network; resets only when asked,
 * as a reset ends the session (FAST STOP on the device) and tests the
 * driver's reconnection, not its reading. */
static const struct {
    const char *name;
    const char *items;
} presets[] = {
    {"off", ""},
    {"rough", "split=4,gap=0.5-3,coalesce=2,latency=1,jitter=2,loss=0.02,dup=0.01,reorder=0.02"},
    {"split", "split=4,gap=0.5-3"},
    {"lossy", "latency=2,jitter=4,loss=0.1,dup=0.05,reorder=0.1"},
    {"slow", "latency=20,jitter=10,coalesce=5"},
};

#define PRESET_COUNT (sizeof(presets) / sizeof(presets[0]))

void wire_spec_off(wire_spec_t *spec)
{
    uint64_t seed = spec->seed; /* a named seed stays: it is the run's */
    bool seed_set = spec->seed_set;
    memset(spec, 0, sizeof(*spec));
    spec->seed = seed;
    spec->seed_set = seed_set;
}

bool wire_spec_active(const wire_spec_t *spec)
{
    return spec->split > 1u || spec->coalesce_us > 0u || spec->reset_us > 0u ||
           spec->latency_us > 0u || spec->jitter_us > 0u || spec->loss > 0.0 || spec->dup > 0.0 ||
           spec->reorder > 0.0;
}

static bool fail(char *why, size_t cap, const char *fmt, const char *what)
{
    snprintf(why, cap, fmt, what);
    return false;
}

/* A plain decimal number (no sign, hex, inf or nan). */
static bool read_decimal(const char *text, double *out)
{
    if (text[0] == '\0' || strspn(text, "0123456789.") != strlen(text)) {
        return false;
    }
    char *end = NULL;
    errno = 0;
    double v = strtod(text, &end);
    if (errno != 0 || end == text || *end != '\0' || !isfinite(v)) {
        return false;
    }
    *out = v;
    return true;
}

/* Milliseconds to µs within [0, max_us]. */
static bool read_ms(const char *text, uint64_t max_us, uint64_t *us)
{
    double ms = 0.0;
    if (!read_decimal(text, &ms) || ms * 1000.0 > (double)max_us) {
        return false;
    }
    *us = (uint64_t)llround(ms * 1000.0);
    return true;
}

static bool read_probability(const char *text, double *p)
{
    return read_decimal(text, p) && *p >= 0.0 && *p <= 1.0;
}

static bool read_whole(const char *text, uint64_t max, uint64_t *out)
{
    if (text[0] == '\0' || strspn(text, "0123456789") != strlen(text) || strlen(text) > 20) {
        return false;
    }
    errno = 0;
    unsigned long long v = strtoull(text, NULL, 10);
    if (errno != 0 || v > max) {
        return false;
    }
    *out = v;
    return true;
}

/* gap=MS or gap=MS-MS */
static bool read_gap(wire_spec_t *spec, const char *value)
{
    char lo[ITEM_MAX];
    size_t n = strlen(value);
    if (n >= sizeof(lo)) {
        return false;
    }
    memcpy(lo, value, n + 1u);
    char *dash = strchr(lo, '-');
    const char *hi = dash != NULL ? dash + 1 : lo;
    if (dash != NULL) {
        *dash = '\0';
    }
    uint64_t min_us = 0, max_us = 0;
    if (!read_ms(lo, WIRE_TIME_MAX_US, &min_us) || !read_ms(hi, WIRE_TIME_MAX_US, &max_us) ||
        min_us > max_us) {
        return false;
    }
    spec->gap_min_us = (uint32_t)min_us;
    spec->gap_max_us = (uint32_t)max_us;
    return true;
}

static bool read_time(const char *value, uint32_t *field)
{
    uint64_t us = 0;
    if (!read_ms(value, WIRE_TIME_MAX_US, &us)) {
        return false;
    }
    *field = (uint32_t)us;
    return true;
}

static bool read_split(wire_spec_t *spec, const char *value)
{
    uint64_t n = 0;
    if (!read_whole(value, WIRE_SPLIT_MAX, &n)) {
        return false;
    }
    spec->split = n > 1u ? (uint32_t)n : 0u;
    if (spec->split > 0u && spec->gap_max_us == 0u) {
        spec->gap_min_us = 500u; /* a split with no gap given: 0.5-3 ms */
        spec->gap_max_us = 3000u;
    }
    return true;
}

/* One KEY=VALUE item; false when the key is unknown or its value bad. */
static bool apply_item(wire_spec_t *spec, const char *key, const char *value)
{
    if (strcasecmp(key, "split") == 0) {
        return read_split(spec, value);
    }
    if (strcasecmp(key, "gap") == 0) {
        return read_gap(spec, value);
    }
    if (strcasecmp(key, "coalesce") == 0) {
        return read_time(value, &spec->coalesce_us);
    }
    if (strcasecmp(key, "latency") == 0) {
        return read_time(value, &spec->latency_us);
    }
    if (strcasecmp(key, "jitter") == 0) {
        return read_time(value, &spec->jitter_us);
    }
    if (strcasecmp(key, "reset") == 0) {
        return read_ms(value, WIRE_RESET_MAX_US, &spec->reset_us);
    }
    if (strcasecmp(key, "loss") == 0) {
        return read_probability(value, &spec->loss);
    }
    if (strcasecmp(key, "dup") == 0) {
        return read_probability(value, &spec->dup);
    }
    if (strcasecmp(key, "reorder") == 0) {
        return read_probability(value, &spec->reorder);
    }
    if (strcasecmp(key, "seed") == 0) {
        if (!read_whole(value, UINT64_MAX, &spec->seed)) {
            return false;
        }
        spec->seed_set = true;
        return true;
    }
    return false;
}

static const char *const keys_help =
    "split=N (2-16), gap=MS[-MS], coalesce=MS, latency=MS, jitter=MS, reset=MS, loss=P, dup=P, "
    "reorder=P (0-1), seed=N";

static int preset_index(const char *name)
{
    for (size_t i = 0; i < PRESET_COUNT; i++) {
        if (strcasecmp(presets[i].name, name) == 0) {
            return (int)i;
        }
    }
    return -1;
}

static bool apply_items(wire_spec_t *spec, const char *text, bool first_may_be_preset, char *why,
                        size_t cap);

/* One item of text: a preset (first only) or KEY=VALUE. */
static bool apply_one(wire_spec_t *spec, const char *item, bool first, char *why, size_t cap)
{
    char copy[ITEM_MAX];
    size_t len = strlen(item);
    if (len == 0) {
        return fail(why, cap, "an empty item%s", "");
    }
    if (len >= sizeof(copy)) {
        return fail(why, cap, "item too long: %.40s...", item);
    }
    memcpy(copy, item, len + 1u);
    char *eq = strchr(copy, '=');
    if (eq == NULL) {
        int p = preset_index(copy);
        if (p < 0 || !first) {
            snprintf(why, cap, "%s %s (presets: off, rough, split, lossy, slow; first only)",
                     p < 0 ? "unknown preset" : "a preset comes first:", copy);
            return false;
        }
        wire_spec_off(spec);
        return apply_items(spec, presets[p].items, false, why, cap);
    }
    *eq = '\0';
    if (!apply_item(spec, copy, eq + 1)) {
        snprintf(why, cap, "bad item %.30s=%.30s (%s)", copy, eq + 1, keys_help);
        return false;
    }
    return true;
}

static bool apply_items(wire_spec_t *spec, const char *text, bool first_may_be_preset, char *why,
                        size_t cap)
{
    const char *at = text;
    bool first = first_may_be_preset;
    while (*at != '\0') {
        size_t len = strcspn(at, ",");
        char item[ITEM_MAX + 1]; /* one longer than an item may be: apply_one() says so */
        size_t kept = len < ITEM_MAX ? len : ITEM_MAX;
        memcpy(item, at, kept);
        item[kept] = '\0';
        if (!apply_one(spec, item, first, why, cap)) {
            return false;
        }
        first = false;
        at += len;
        if (*at == ',' && *++at == '\0') {
            return fail(why, cap, "an empty item%s", "");
        }
    }
    return true;
}

bool wire_spec_parse(wire_spec_t *spec, const char *text, char *why, size_t cap)
{
    wire_spec_t trial = *spec;
    if (text[0] == '\0') {
        return fail(why, cap, "empty; a preset (off, rough, split, lossy, slow) or %s", keys_help);
    }
    if (!apply_items(&trial, text, true, why, cap)) {
        return false;
    }
    *spec = trial;
    return true;
}

/* Milliseconds as the parser reads them: 0.5, 3, 0.001. */
static void put_ms(char *out, size_t cap, uint64_t us)
{
    snprintf(out, cap, "%.3f", (double)us / 1000.0);
    char *end = out + strlen(out) - 1;
    while (*end == '0') {
        *end-- = '\0';
    }
    if (*end == '.') {
        *end = '\0';
    }
}

static void append(char *out, size_t cap, const char *key, const char *value)
{
    size_t used = strlen(out);
    snprintf(out + used, cap - used, "%s%s=%s", used > 0 ? "," : "", key, value);
}

static void append_ms(char *out, size_t cap, const char *key, uint64_t us)
{
    char ms[32];
    if (us > 0u) {
        put_ms(ms, sizeof(ms), us);
        append(out, cap, key, ms);
    }
}

static void append_p(char *out, size_t cap, const char *key, double p)
{
    char text[32];
    if (p > 0.0) {
        snprintf(text, sizeof(text), "%.6g", p);
        append(out, cap, key, text);
    }
}

void wire_spec_format(const wire_spec_t *spec, char *out, size_t cap)
{
    char text[32];
    out[0] = '\0';
    if (spec->split > 1u) {
        char lo[16], hi[16];
        snprintf(text, sizeof(text), "%u", spec->split);
        append(out, cap, "split", text);
        put_ms(lo, sizeof(lo), spec->gap_min_us);
        put_ms(hi, sizeof(hi), spec->gap_max_us);
        snprintf(text, sizeof(text), "%s%s%s", lo, spec->gap_min_us != spec->gap_max_us ? "-" : "",
                 spec->gap_min_us != spec->gap_max_us ? hi : "");
        append(out, cap, "gap", text);
    }
    append_ms(out, cap, "coalesce", spec->coalesce_us);
    append_ms(out, cap, "latency", spec->latency_us);
    append_ms(out, cap, "jitter", spec->jitter_us);
    append_ms(out, cap, "reset", spec->reset_us);
    append_p(out, cap, "loss", spec->loss);
    append_p(out, cap, "dup", spec->dup);
    append_p(out, cap, "reorder", spec->reorder);
    if (out[0] == '\0') {
        snprintf(out, cap, "off");
    }
}

static uint64_t splitmix64(uint64_t *state)
{
    uint64_t z = (*state += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

void wire_rng_seed(wire_rng_t *rng, uint64_t seed, uint64_t stream)
{
    uint64_t mix = stream;
    rng->state = seed ^ splitmix64(&mix);
}

uint64_t wire_rng_next(wire_rng_t *rng)
{
    return splitmix64(&rng->state);
}

double wire_rng_unit(wire_rng_t *rng)
{
    return (double)(wire_rng_next(rng) >> 11) * (1.0 / 9007199254740992.0);
}

uint64_t wire_rng_range(wire_rng_t *rng, uint64_t lo, uint64_t hi)
{
    uint64_t span = hi - lo;
    return span == UINT64_MAX ? wire_rng_next(rng) : lo + wire_rng_next(rng) % (span + 1u);
}
