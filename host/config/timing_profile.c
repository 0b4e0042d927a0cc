/* SPDX-License-Identifier: BSD-3-Clause */
#include "timing_profile.h"

#include "data_dir.h"

#include <fcntl.h>
#include <ini.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#ifndef WSGSIM_TIMING_DIR
#define WSGSIM_TIMING_DIR "/usr/share/wsgsim/timing"
#endif

/* A figure's key in [timing] (milliseconds, fractions allowed) and where
 * it goes. */
typedef struct {
    const char *key;
    size_t offset; /* of its uint32_t µs in wsg_timing_t */
} figure_t;

#define FIGURE(key, field)                                                                         \
    {                                                                                              \
        key, offsetof(wsg_timing_t, field)                                                         \
    }

static const figure_t figures[] = {
    FIGURE("query_ms", service[WSG_REQ_QUERY].mean_us),
    FIGURE("query_spread_ms", service[WSG_REQ_QUERY].spread_us),
    FIGURE("motion_ms", service[WSG_REQ_MOTION].mean_us),
    FIGURE("motion_spread_ms", service[WSG_REQ_MOTION].spread_us),
    FIGURE("setting_ms", service[WSG_REQ_SETTING].mean_us),
    FIGURE("setting_spread_ms", service[WSG_REQ_SETTING].spread_us),
    FIGURE("script_ms", service[WSG_REQ_SCRIPT].mean_us),
    FIGURE("script_spread_ms", service[WSG_REQ_SCRIPT].spread_us),
    FIGURE("stream_frame_ms", stream_frame_us),
    FIGURE("update_floor_ms", update_floor_us),
};

#define FIGURE_COUNT (sizeof(figures) / sizeof(figures[0]))
#define FIGURE_MAX_MS 10000.0 /* 10 s: more is no device's pace */
#define PROFILE_MAX_BYTES (64 * 1024)

typedef struct {
    wsg_timing_t timing;
    bool set[FIGURE_COUNT];
    char *why;
} reading_t;

static int take_key(void *user, const char *section, const char *key, const char *value)
{
    reading_t *r = user;
    if (strcmp(section, "timing") != 0) {
        return 1; /* other sections are other readers' ([device], [mechanics], ...) */
    }
    for (size_t i = 0; i < FIGURE_COUNT; i++) {
        if (strcmp(key, figures[i].key) != 0) {
            continue;
        }
        char *end = NULL;
        double ms = strtod(value, &end);
        if (end == value || *end != '\0' || !isfinite(ms) || ms < 0.0 || ms > FIGURE_MAX_MS) {
            snprintf(r->why, TIMING_WHY_MAX, "[timing] %s = '%s': expected milliseconds 0-%.0f",
                     key, value, FIGURE_MAX_MS);
            return 0;
        }
        uint32_t us = (uint32_t)lround(ms * 1000.0);
        memcpy((char *)&r->timing + figures[i].offset, &us, sizeof(us));
        r->set[i] = true;
        return 1;
    }
    snprintf(r->why, TIMING_WHY_MAX, "[timing] %s: unknown key (see docs/timing.md)", key);
    return 0;
}

/* Every figure set, and each spread within its mean. */
static bool complete(reading_t *r)
{
    for (size_t i = 0; i < FIGURE_COUNT; i++) {
        if (!r->set[i]) {
            snprintf(r->why, TIMING_WHY_MAX, "[timing] %s missing: a profile sets every figure",
                     figures[i].key);
            return false;
        }
    }
    for (unsigned k = 0; k < WSG_REQ_KIND_COUNT; k++) {
        if (r->timing.service[k].spread_us > r->timing.service[k].mean_us) {
            snprintf(r->why, TIMING_WHY_MAX, "[timing] %s: a spread larger than its mean",
                     figures[2u * k + 1u].key);
            return false;
        }
    }
    return true;
}

static bool is_name(const char *spec)
{
    return spec[0] != '\0' && strchr(spec, '/') == NULL && strchr(spec, '.') == NULL;
}

void timing_profile_dir(char *dir, size_t cap)
{
    data_dir_find("profiles/timing", "wsg50.ini", WSGSIM_TIMING_DIR, dir, cap);
}

/* A regular file of at most PROFILE_MAX_BYTES, opened without blocking: a
 * FIFO or a device named as a profile must not hang the start or the
 * control channel. */
static FILE *open_profile(const char *path)
{
    int fd = open(path, O_RDONLY | O_NONBLOCK | O_CLOEXEC);
    struct stat st;
    if (fd < 0 || fstat(fd, &st) != 0 || !S_ISREG(st.st_mode) || st.st_size > PROFILE_MAX_BYTES) {
        if (fd >= 0) {
            close(fd);
        }
        return NULL;
    }
    FILE *f = fdopen(fd, "r");
    if (f == NULL) {
        close(fd);
    }
    return f;
}

static bool read_file(const char *path, const char *spec, reading_t *r)
{
    FILE *f = open_profile(path);
    if (f == NULL) {
        snprintf(r->why, TIMING_WHY_MAX,
                 is_name(spec) ? "no timing profile '%.64s' (shipped: ideal, wsg50; or an INI path)"
                               : "cannot read timing profile '%.160s' (a regular file of at "
                                 "most 64 KiB)",
                 spec);
        return false;
    }
    int line = ini_parse_file(f, take_key, r);
    fclose(f);
    if (line > 0 && r->why[0] == '\0') {
        snprintf(r->why, TIMING_WHY_MAX, "%.160s:%d: not an INI line", path, line);
    }
    return line == 0 && complete(r);
}

bool timing_profile_load(const char *spec, wsg_timing_t *out, char *why)
{
    why[0] = '\0';
    if (spec == NULL || strcmp(spec, TIMING_PROFILE_IDEAL) == 0) {
        uint64_t seed = out->seed;
        *out = (wsg_timing_t){.seed = seed};
        return true;
    }
    char path[PATH_MAX];
    if (is_name(spec)) {
        char dir[PATH_MAX - 64];
        timing_profile_dir(dir, sizeof(dir));
        snprintf(path, sizeof(path), "%s/%.48s.ini", dir, spec);
    } else {
        snprintf(path, sizeof(path), "%s", spec);
    }
    reading_t r = {.why = why};
    if (!read_file(path, spec, &r)) {
        return false;
    }
    r.timing.enabled = true;
    r.timing.seed = out->seed;
    *out = r.timing;
    return true;
}
