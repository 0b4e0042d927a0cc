/* SPDX-License-Identifier: BSD-3-Clause */
/* Device identity and configuration: what the real WSG keeps in its
 * configuration memory and edits through its web interface. The port fills
 * one in and hands it to wsg_device_init(); the device keeps its own copy,
 * which run-time settings (wsg_device.h) then change. */
#ifndef WSG_CONFIG_H
#define WSG_CONFIG_H

#include <stdbool.h>
#include <stdint.h>

#include "wsg_opts.h"

#define WSG_CONFIG_STRING_MAX 48

/* The kinds of request a timing profile gives service times of. */
typedef enum {
    WSG_REQ_QUERY,   /* a GCL query (NAME?), a binary read (0x40-0x4F, 0x50-0x5F) */
    WSG_REQ_MOTION,  /* a command that starts or ends a motion (MOVE, GRIP, STOP, 0x20-0x26) */
    WSG_REQ_SETTING, /* every other command (settings, system commands) */
    WSG_REQ_SCRIPT,  /* a binary command a user script registered (custom command) */
    WSG_REQ_KIND_COUNT
} wsg_request_kind_t;

/* A service time: uniform on [mean - spread, mean + spread] (µs). */
typedef struct {
    uint32_t mean_us;
    uint32_t spread_us;
} wsg_service_time_t;

/* The device's pace (docs/timing.md). Not enabled: the "ideal" profile,
 * every request answered the instant it arrives. Enabled: one command
 * processor serves the requests of all connections one at a time in
 * arrival order, each for a service time of its kind, and each stream
 * frame (AUTOSEND, binary automatic updates) occupies it for
 * stream_frame_us. Jitter comes from the device's own generator, seeded
 * from `seed`. */
typedef struct {
    bool enabled;
    wsg_service_time_t service[WSG_REQ_KIND_COUNT];
    uint32_t stream_frame_us;
    uint32_t update_floor_us; /* shortest binary automatic update period */
    uint64_t seed;
} wsg_timing_t;
/* A gripper's mechanics beyond its datasheet (the configuration file's
 * [mechanics]): how long the firmware waits before it believes a
 * condition, and how the drive follows its commands. A calibration fits
 * them to a user's own gripper. Every field's 0 means the built-in value
 * (firmware/priv/motion_tuning.h, hal/sim), so a configuration that never
 * sets them behaves as the device always did. */
typedef struct {
    uint32_t settle_us;            /* in position (or pressing) before FIN */
    uint32_t block_detect_us;      /* a MOVE blocked before ERR 29 */
    uint32_t home_block_detect_us; /* homing: at the end stop before the origin */
    uint32_t part_lost_us;         /* a weak grip before PART LOST */
    float speed_limit_mm_s;        /* the drive's top speed (below the model's maximum) */
    float accel_scale;             /* the share of the commanded acceleration reached */
    float stop_decel_mm_s2;        /* STOP's deceleration (0: the motion's acceleration) */
    float fast_stop_decel_mm_s2;   /* FAST STOP's deceleration */
    float force_rise_n_s;          /* the grip force's rise on contact (0: at once) */
} wsg_mechanics_t;

typedef struct {
    /* identity */
    char devtype[WSG_CONFIG_STRING_MAX]; /* e.g. "WSG 50-110" */
    char version[WSG_CONFIG_STRING_MAX]; /* firmware version string, e.g. "4.0.0" */
    char tag[WSG_CONFIG_STRING_MAX];     /* descriptor string (device tag) */
    uint32_t serial;
    uint8_t hw_revision; /* the binary system information's hardware revision */

    /* mechanics of the model */
    float stroke_mm;
    float speed_min_mm_s, speed_max_mm_s;
    float accel_min_mm_s2, accel_max_mm_s2;
    float force_min_n, force_max_n; /* nominal gripping force range */
    float force_overdrive_n;        /* 0: the model has no overdrive mode */
    bool overdrive_mode;            /* overdrive enabled in the configuration */

    /* motion configuration (web interface "Motion Configuration") */
    float default_speed_mm_s;
    float default_accel_mm_s2;
    float default_force_n;
    float default_pullback_mm;
    float default_pwt_mm; /* part width tolerance */
    float default_clt_mm; /* clamping travel */
    bool soft_limits_enabled;
    float soft_limit_minus_mm, soft_limit_plus_mm;
    bool home_positive; /* default homing direction */
    float homing_speed_mm_s;
    wsg_mechanics_t mechanics;

    /* behaviour */
    bool disconnect_raises_faststop;
    bool bin_crc_unchecked; /* binary protocol: checksums read and ignored (default: checked) */
    bool move_retarget;     /* a MOVE during a MOVE retargets it; false: ERR MOVE 4 */
    float temp_warning_c, temp_fault_c;

    wsg_timing_t timing; /* the device's pace (zero: ideal) */
} wsg_config_t;

/* The device's policy, stated once (firmware/core/policy.c): every
 * protocol, the configuration file and the control channel use these. */

/* The largest grip force: the overdrive force when the model has one and
 * overdrive mode is on, else the nominal maximum. */
float wsg_config_force_max(const wsg_config_t *cfg);
bool wsg_config_force_ok(const wsg_config_t *cfg, float force_n);
bool wsg_config_speed_ok(const wsg_config_t *cfg, float speed_mm_s);
bool wsg_config_accel_ok(const wsg_config_t *cfg, float accel_mm_s2);
/* The travel a target may have: the stroke, narrowed by soft limits. */
void wsg_config_travel(const wsg_config_t *cfg, float *low_mm, float *high_mm);
bool wsg_config_target_ok(const wsg_config_t *cfg, float target_mm);
/* A length within the stroke (PWT, CLT, pull-back, a grip width). */
bool wsg_config_length_ok(const wsg_config_t *cfg, float mm);
/* Soft limits inside the stroke and in order; false with a reason. */
bool wsg_config_check(const wsg_config_t *cfg, const char **why);
/* A character a device text (the tag) may hold: printable ASCII (0x20 to
 * 0x7E) but '"'. GCL's TAG? quotes the tag on one line, so CR, LF or '"'
 * would let a tag forge or end a reply; no front end may store one. */
bool wsg_config_text_char_ok(char c);

#endif
