/* SPDX-License-Identifier: BSD-3-Clause */
#include "record.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "hal_clock.h"
#include "record_file.h"

/* The device's state is sampled at most this often (100 Hz of simulated
 * time), at control steps that run anyway: an idle device makes none. */
#define SAMPLE_PERIOD_US 10000u
/* A sample is written when a reading moved by this much since the last
 * one written (or the motion or grip state changed): a held part's force
 * noise (about 0.05 N) writes nothing, a moving jaw a line per period. */
#define SAMPLE_POS_STEP_MM 0.01f
#define SAMPLE_SPEED_STEP_MM_S 0.1f
#define SAMPLE_FORCE_STEP_N 0.1f

/* What the record attaches to one device: its message observer, which
 * device the channel names, and its last state sample. */
typedef struct {
    record_t *record;
    unsigned index;
    wsg_conn_observer_t messages;
    uint64_t next_sample_us;    /* no sample before, unless the motion changed */
    wsg_motion_kind_t motion;   /* the motion at the last sample */
    uint64_t motion_started_us; /* and when it started */
    bool sampled;               /* a sample was written; its readings: */
    float position_mm, speed_mm_s, force_n;
    wsg_grip_state_t grip_state;
} record_device_t;

struct record {
    FILE *out;
    const char *path;
    bool name_devices; /* more than one device: "d2.s1t" instead of "s1t" */
    unsigned count;
    record_device_t devices[];
};

record_t *record_open(const char *path, unsigned devices)
{
    record_t *r = calloc(1, sizeof(*r) + devices * sizeof(r->devices[0]));
    FILE *f = r != NULL ? record_file_open(path, "w", _IOLBF) : NULL;
    if (f == NULL) {
        fprintf(stderr, "wsgsim: cannot write --record file %s: %s\n", path, strerror(errno));
        free(r);
        return NULL;
    }
    r->out = f;
    r->path = path;
    r->name_devices = devices > 1;
    r->count = devices;
    return r;
}

bool record_reopen(record_t *r)
{
    if (r == NULL) {
        return true;
    }
    FILE *f = record_file_open(r->path, "a", _IOLBF);
    if (f == NULL) {
        return false;
    }
    fclose(r->out);
    r->out = f;
    return true;
}

/* The record's lines carry the simulated time of the device's clock. */
static void put_record(FILE *out, const char *channel, char direction, const char *line, size_t len)
{
    record_file_put(out, hal_clock_now_us(), channel, direction, line, len);
}

static void record_gcl(const record_device_t *rd, const wsg_conn_t *c, char direction,
                       const char *line, size_t len)
{
    char device[16] = "";
    if (rd->record->name_devices) {
        snprintf(device, sizeof(device), "d%u.", rd->index);
    }
    char channel[48];
    snprintf(channel, sizeof(channel), "%ss%llu%c", device, (unsigned long long)wsg_conn_id(c),
             wsg_conn_transport(c) == WSG_TRANSPORT_STREAM ? 't' : 'u');
    put_record(rd->record->out, channel, direction, line, len);
}

/* Written from the client's side, as a transcript reads: '>' it sent. */
static void on_in(void *ctx, const wsg_conn_t *c, const char *line, size_t len)
{
    record_gcl(ctx, c, '>', line, len);
}

static void on_out(void *ctx, const wsg_conn_t *c, const char *line, size_t len)
{
    record_gcl(ctx, c, '<', line, len);
}

void record_attach(record_t *r, wsg_device_t *dev, unsigned index)
{
    if (r == NULL || index >= r->count) {
        return;
    }
    record_device_t *rd = &r->devices[index];
    *rd = (record_device_t){.record = r, .index = index, .motion = WSG_MOTION_NONE};
    rd->messages = (wsg_conn_observer_t){.message_in = on_in, .message_out = on_out, .ctx = rd};
    wsg_conn_add_observer(dev, &rd->messages);
}

void record_detach(record_t *r, wsg_device_t *dev, unsigned index)
{
    if (r != NULL && index < r->count) {
        wsg_conn_remove_observer(dev, &r->devices[index].messages);
    }
}

void record_control(record_t *r, const char *channel, char direction, const char *line, size_t len)
{
    if (r != NULL) {
        put_record(r->out, channel, direction == '<' ? '>' : '<', line, len);
    }
}

/* A reading as GCL writes it: fixed point, one to three decimals. */
static void format_reading(float value, char *out, size_t cap)
{
    int len = snprintf(out, cap, "%.3f", (double)value);
    if (len < 0 || (size_t)len >= cap) {
        return; /* no physical reading is that long: the cut text stays */
    }
    while (len > 2 && out[len - 1] == '0' && out[len - 2] != '.') {
        out[--len] = '\0';
    }
}

static bool moved(float now, float before, float step)
{
    return now - before >= step || before - now >= step;
}

/* Whether the snapshot differs from the last sample written enough to
 * write another. */
static bool worth_a_sample(const record_device_t *rd, const wsg_snapshot_t *s)
{
    return !rd->sampled || s->grip_state != rd->grip_state ||
           moved(s->position_mm, rd->position_mm, SAMPLE_POS_STEP_MM) ||
           moved(s->speed_mm_s, rd->speed_mm_s, SAMPLE_SPEED_STEP_MM_S) ||
           moved(s->force_n, rd->force_n, SAMPLE_FORCE_STEP_N);
}

/* "POS=.. SPEED=.. FORCE=.. GRIPSTATE=n", the names of the GCL queries. */
static void describe_state(const wsg_snapshot_t *s, char *out, size_t cap)
{
    char position[24], speed[24], force[24];
    format_reading(s->position_mm, position, sizeof(position));
    format_reading(s->speed_mm_s, speed, sizeof(speed));
    format_reading(s->force_n, force, sizeof(force));
    snprintf(out, cap, "POS=%s SPEED=%s FORCE=%s GRIPSTATE=%d", position, speed, force,
             (int)s->grip_state);
}

void record_sample(record_t *r, unsigned index, wsg_device_t *dev)
{
    if (r == NULL || index >= r->count) {
        return;
    }
    record_device_t *rd = &r->devices[index];
    uint64_t now = hal_clock_now_us();
    uint64_t started = 0;
    wsg_motion_kind_t motion = wsg_device_motion(dev, &started);
    bool motion_changed = motion != rd->motion || started != rd->motion_started_us;
    if (!motion_changed && now < rd->next_sample_us) {
        return; /* most steps of a motion: one sample per period */
    }
    rd->next_sample_us = now - now % SAMPLE_PERIOD_US + SAMPLE_PERIOD_US;
    const wsg_snapshot_t *s = wsg_device_snapshot(dev);
    if (!motion_changed && !worth_a_sample(rd, s)) {
        return;
    }
    rd->motion = motion;
    rd->motion_started_us = started;
    rd->sampled = true;
    rd->position_mm = s->position_mm;
    rd->speed_mm_s = s->speed_mm_s;
    rd->force_n = s->force_n;
    rd->grip_state = s->grip_state;
    char text[128]; /* the longest the readings can make */
    describe_state(s, text, sizeof(text));
    char channel[16] = "dev";
    if (r->name_devices) {
        snprintf(channel, sizeof(channel), "d%u.dev", index);
    }
    put_record(r->out, channel, '=', text, strlen(text));
}

void record_close(record_t *r)
{
    if (r != NULL) {
        fclose(r->out);
        free(r);
    }
}
