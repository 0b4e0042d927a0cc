/* SPDX-License-Identifier: BSD-3-Clause */
/* The plant: the gripper's mechanics and the scene around it, computed by
 * a physics engine in lock-step with the device (docs/physics.md). Per
 * control step the device's drive hands the plant its command (a servo
 * setpoint and a force limit) and the time to advance; the plant returns
 * the jaws' opening, speed, the motor's and the contacts' forces and the
 * finger pads' readings. Between steps the scene can be read (bodies'
 * poses, contacts) and steered (a body placed, pushed, made heavier or
 * slipperier).
 *
 * An instance is an ops table and its context (as the HAL's devices):
 * MuJoCo in-process (physics_mujoco.c) is one implementation; another
 * engine can stand behind the same table (a process over a socket). Units:
 * the jaws in mm and N as the device sees them, the scene in SI (m, kg, N)
 * in the scene's world frame. Deterministic: the same calls in the same
 * order give bit-identical results. */
#ifndef HOST_PLANT_H
#define HOST_PLANT_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#define PLANT_FINGERS 2u
/* a finger pad's tactile cells, as the DSA finger's (docs/finger-bus.md) */
#define PLANT_PAD_ROWS 14u
#define PLANT_PAD_COLS 6u
#define PLANT_PAD_CELLS (PLANT_PAD_ROWS * PLANT_PAD_COLS)
#define PLANT_NAME_MAX 48u

/* What the drive commands for the next step. The plant's servo pushes the
 * jaws towards the setpoint, its force clamped to force_limit_n: the
 * grip force each finger exerts when the jaws press on something. */
typedef struct {
    bool enabled;        /* false: the drive is off, the motor exerts no force */
    float position_mm;   /* setpoint: the jaws' opening (0: the fingers touch) */
    float velocity_mm_s; /* the setpoint's rate (feed-forward), positive opening */
    float force_limit_n; /* the most the motor pushes with, > 0 */
} plant_drive_t;

/* One finger's pad after a step. */
typedef struct {
    float force_n;                  /* normal force of every contact on the pad, >= 0 */
    float cells_n[PLANT_PAD_CELLS]; /* that force over the cells, row-major, row 0 at the tip */
} plant_pad_t;

/* The plant after a step. */
typedef struct {
    uint64_t time_us;    /* the plant's time: the sum of its steps */
    float width_mm;      /* the jaws' opening (0: the fingers touch) */
    float velocity_mm_s; /* its rate, positive opening */
    float motor_force_n; /* what the motor exerts, positive opening */
    float jaw_force_n;   /* contact force on the jaws (not the end stops'): the pads' mean */
    plant_pad_t pad[PLANT_FINGERS]; /* 0: left, 1: right */
    bool quiet;                     /* nothing in the scene moved in this step */
    bool fault; /* the engine is lost (a plant process that died, answered garbage or
                 * not in time): the readings are its last, the jaws stand */
} plant_sample_t;

/* A body of the scene. */
typedef struct {
    char name[PLANT_NAME_MAX];
    double pos_m[3];   /* its frame's origin in the world */
    double quat[4];    /* its orientation (w, x, y, z) */
    double vel_m_s[3]; /* its origin's speed */
    double mass_kg;    /* its own mass (0 for the world) */
    double friction;   /* its first collision shape's sliding friction (0: none) */
    bool free;         /* it moves on its own (a free joint) */
    bool mocap;        /* the scene moves it (the gripper's base) */
} plant_body_t;

/* A contact between two bodies, as the engine resolved it in the last step. */
typedef struct {
    unsigned body[2]; /* the bodies' indices (plant_ops_t.body) */
    double pos_m[3];  /* where, in the world */
    double normal[3]; /* from body[0] to body[1] */
    double normal_n;  /* the normal force, >= 0 */
    double tangent_n; /* the friction force's magnitude */
} plant_contact_t;

/* What a scene change sets (plant_ops_t.set). */
typedef enum {
    PLANT_SET_POSITION, /* value[3]: m; a free body at rest there, a mocap body moved */
    PLANT_SET_VELOCITY, /* value[3]: m/s; a free body's or a mocap body's speed */
    PLANT_SET_FORCE,    /* value[3]: N on a free body's centre, held until set again */
    PLANT_SET_MASS,     /* value[0]: kg > 0, a free body (its inertia scales with it) */
    PLANT_SET_FRICTION, /* value[0]: >= 0, every collision shape of the body */
} plant_set_t;

typedef enum {
    PLANT_OK = 0,
    PLANT_ERR_NO_BODY, /* no body of that index */
    PLANT_ERR_FIXED,   /* the body cannot be moved (neither free nor mocap) */
    PLANT_ERR_VALUE,   /* a value out of range or not finite */
    PLANT_ERR_UNSUPPORTED,
} plant_err_t;

typedef struct {
    const char *name; /* the engine: "mujoco" */
    /* The engine's own step: every dt given to step() is a multiple of it. */
    uint32_t (*timestep_us)(void *ctx);
    /* Advances by dt_us (a multiple of timestep_us) under the drive's
     * command, and fills *out. */
    void (*step)(void *ctx, const plant_drive_t *drive, uint32_t dt_us, plant_sample_t *out);
    /* Back to the scene as loaded, the jaws at width_mm, the time 0. */
    void (*reset)(void *ctx, float width_mm);
    /* The scene's bodies: 0 is the world. */
    unsigned (*body_count)(void *ctx);
    bool (*body)(void *ctx, unsigned index, plant_body_t *out);
    /* The contacts of the last step, at most cap of them; returns how many
     * there are (may exceed cap). */
    unsigned (*contacts)(void *ctx, plant_contact_t *out, unsigned cap);
    /* Changes a body: value holds 3 numbers or 1 (plant_set_t); nothing
     * changes unless PLANT_OK. */
    plant_err_t (*set)(void *ctx, unsigned index, plant_set_t what, const double *value);
    void (*destroy)(void *ctx);
} plant_ops_t;

typedef struct {
    const plant_ops_t *ops;
    void *ctx;
} plant_t;

/* A body's index by its name; false when the scene has none of that name. */
bool plant_find_body(const plant_t *plant, const char *name, unsigned *index);
/* What a plant_err_t says, for a user. */
const char *plant_strerror(plant_err_t err);

#endif
