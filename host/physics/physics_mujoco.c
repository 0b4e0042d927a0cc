/* SPDX-License-Identifier: BSD-3-Clause */
#include "physics_mujoco.h"

#include <math.h>
#include <mujoco/mujoco.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "hal_log.h"
#include "log.h"
#include "physics_mujoco_api.h"

/* The gripper model's names (physics/wsg-gripper.xml). */
#define JOINT_LEFT "wsg_left"
#define JOINT_RIGHT "wsg_right"
#define MOTOR "wsg_motor"
#define HAND "wsg_hand"
static const char *const pad_geoms[PLANT_FINGERS] = {"wsg_pad_left", "wsg_pad_right"};
static const char *const pad_sensors[PLANT_FINGERS] = {"wsg_touch_left", "wsg_touch_right"};

/* A scene file larger than this is refused before the engine reads it. */
#define SCENE_BYTES_MAX (64u << 20)

/* The engine reads what it is given to the end: a FIFO or a device would
 * hold the start forever, so only a regular file of a sane size goes. */
static bool regular_file(const char *path, char *why, size_t cap)
{
    struct stat st;
    if (stat(path, &st) != 0 || !S_ISREG(st.st_mode) || st.st_size > (off_t)SCENE_BYTES_MAX) {
        snprintf(why, cap, "%s: not a regular file of at most %u MiB", path, SCENE_BYTES_MAX >> 20);
        return false;
    }
    return true;
}

/* The in-memory file that includes the gripper and the scene. */
#define TOP_FILE "wsgsim-scene.xml"
/* Below this speed (m/s or rad/s) of every degree of freedom, nothing
 * moves: 10 um/s. A part squeezed between the pads creeps at about 2e-6
 * (the soft contacts' drift), which no reading shows within a second. */
#define QUIET_SPEED 1e-5

typedef struct {
    mjModel *m;
    mjModel *loaded; /* m as loaded (its stroke set): a reset restores it */
    mjData *d;
    int qpos_left, qpos_right; /* the fingers' joints: half the opening each */
    int dof_left, dof_right;
    int motor;
    int pad_geom[PLANT_FINGERS];
    int pad_sensor[PLANT_FINGERS]; /* their touch sensors' address in sensordata */
    double mocap_vel[3];           /* the base's speed (PLANT_SET_VELOCITY) */
    int base_mocap;
    uint32_t timestep_us;
    uint64_t time_us;
} mujoco_plant_t;

static void log_warning(const char *msg)
{
    host_logf(HAL_LOG_WARN, "physics: %s", msg);
}

/* The engine calls this on an error it cannot go on from (a bug of ours or
 * out of memory): it must not return. */
static void fatal_error(const char *msg)
{
    host_logf(HAL_LOG_ERROR, "physics: %s", msg);
    abort();
}

/* The top file: the gripper, then the scene; absolute paths, so that the
 * in-memory file (which has no folder) finds them. */
static bool load_model(mujoco_plant_t *p, const char *gripper, const char *scene, char *why,
                       size_t cap)
{
    char top[8192];
    int len = snprintf(top, sizeof(top),
                       "<mujoco model=\"wsgsim\"><include file=\"%s\"/>"
                       "<include file=\"%s\"/></mujoco>",
                       gripper, scene);
    if (len < 0 || (size_t)len >= sizeof(top) || strchr(scene, '"') != NULL ||
        strchr(gripper, '"') != NULL) {
        snprintf(why, cap, "scene file name too long or not usable");
        return false;
    }
    mjVFS *vfs = malloc(sizeof(*vfs)); /* megabytes: not on the stack */
    if (vfs == NULL) {
        snprintf(why, cap, "out of memory");
        return false;
    }
    physics_mj.mj_defaultVFS(vfs);
    if (physics_mj.mj_makeEmptyFileVFS(vfs, TOP_FILE, len) != 0) {
        free(vfs);
        snprintf(why, cap, "out of memory");
        return false;
    }
    memcpy(vfs->filedata[vfs->nfile - 1], top, (size_t)len);
    char err[1000] = "";
    p->m = physics_mj.mj_loadXML(TOP_FILE, vfs, err, sizeof(err));
    physics_mj.mj_deleteVFS(vfs);
    free(vfs);
    if (p->m == NULL) {
        snprintf(why, cap, "%s", err);
        return false;
    }
    return true;
}

static int id_of(const mjModel *m, int type, const char *name, char *why, size_t cap)
{
    int id = physics_mj.mj_name2id(m, type, name);
    if (id < 0) {
        snprintf(why, cap, "the gripper model has no \"%s\"", name);
    }
    return id;
}

/* The gripper's parts by name; false when the model lacks one. */
static bool find_parts(mujoco_plant_t *p, char *why, size_t cap)
{
    const mjModel *m = p->m;
    int left = id_of(m, mjOBJ_JOINT, JOINT_LEFT, why, cap);
    int right = id_of(m, mjOBJ_JOINT, JOINT_RIGHT, why, cap);
    p->motor = id_of(m, mjOBJ_ACTUATOR, MOTOR, why, cap);
    int base = id_of(m, mjOBJ_BODY, HAND, why, cap);
    if (left < 0 || right < 0 || p->motor < 0 || base < 0) {
        return false;
    }
    p->qpos_left = m->jnt_qposadr[left];
    p->qpos_right = m->jnt_qposadr[right];
    p->dof_left = m->jnt_dofadr[left];
    p->dof_right = m->jnt_dofadr[right];
    p->base_mocap = m->body_mocapid[base];
    for (unsigned i = 0; i < PLANT_FINGERS; i++) {
        p->pad_geom[i] = id_of(m, mjOBJ_GEOM, pad_geoms[i], why, cap);
        int sensor = id_of(m, mjOBJ_SENSOR, pad_sensors[i], why, cap);
        if (p->pad_geom[i] < 0 || sensor < 0) {
            return false;
        }
        p->pad_sensor[i] = m->sensor_adr[sensor];
    }
    double step_us = m->opt.timestep * 1e6;
    p->timestep_us = (uint32_t)lround(step_us);
    if (p->timestep_us == 0u || 1000u % p->timestep_us != 0u ||
        fabs(step_us - p->timestep_us) > 1e-6) {
        snprintf(why, cap, "the timestep must divide 1 ms (it is %g s)", m->opt.timestep);
        return false;
    }
    return true;
}

static void set_stroke(mujoco_plant_t *p, float stroke_mm)
{
    mjModel *m = p->m;
    for (int j = 0; j < m->njnt; j++) {
        if (m->jnt_qposadr[j] == p->qpos_left || m->jnt_qposadr[j] == p->qpos_right) {
            m->jnt_range[2 * j] = 0.0;
            m->jnt_range[2 * j + 1] = stroke_mm * 0.5e-3;
        }
    }
}

static void mujoco_reset(void *ctx, float width_mm)
{
    mujoco_plant_t *p = ctx;
    physics_mj.mj_copyModel(p->m, p->loaded); /* masses and frictions as loaded */
    physics_mj.mj_resetData(p->m, p->d);
    p->d->qpos[p->qpos_left] = width_mm * 0.5e-3;
    p->d->qpos[p->qpos_right] = width_mm * 0.5e-3;
    memset(p->mocap_vel, 0, sizeof(p->mocap_vel));
    p->time_us = 0u;
    physics_mj.mj_forward(p->m, p->d);
}

static uint32_t mujoco_timestep_us(void *ctx)
{
    return ((const mujoco_plant_t *)ctx)->timestep_us;
}

/* The servo: force = kp * (ctrl - opening) - kv * rate (the model's
 * actuator), so ctrl = setpoint + kv / kp * setpoint rate tracks both. */
static void command_drive(mujoco_plant_t *p, const plant_drive_t *drive)
{
    mjModel *m = p->m;
    int u = p->motor;
    double limit = drive->enabled ? drive->force_limit_n : 0.0;
    m->actuator_forcerange[2 * u] = -limit;
    m->actuator_forcerange[2 * u + 1] = limit;
    double kp = m->actuator_gainprm[u * mjNGAIN];
    double kv = -m->actuator_biasprm[u * mjNBIAS + 2];
    double lead = kp > 0.0 ? kv / kp : 0.0;
    p->d->ctrl[u] = drive->position_mm * 1e-3 + lead * drive->velocity_mm_s * 1e-3;
}

static bool all_quiet(const mujoco_plant_t *p)
{
    for (int i = 0; i < p->m->nv; i++) {
        if (fabs(p->d->qvel[i]) > QUIET_SPEED) {
            return false;
        }
    }
    return p->mocap_vel[0] == 0.0 && p->mocap_vel[1] == 0.0 && p->mocap_vel[2] == 0.0;
}

static void move_base(mujoco_plant_t *p)
{
    if (p->base_mocap < 0) {
        return;
    }
    for (int k = 0; k < 3; k++) {
        p->d->mocap_pos[3 * p->base_mocap + k] += p->mocap_vel[k] * p->m->opt.timestep;
    }
}

/* The row and column of the cell under a point in a pad's frame (y across
 * the pad, z along it, row 0 at the tip), clamped to the pad. */
static void cell_of(const mjModel *m, int geom, const double local[3], double *row, double *col)
{
    const double *half = &m->geom_size[3 * geom];
    *col = (local[1] + half[1]) / (2.0 * half[1]) * PLANT_PAD_COLS;
    *row = (local[2] + half[2]) / (2.0 * half[2]) * PLANT_PAD_ROWS;
    *col = *col < 0.0 ? 0.0 : (*col > PLANT_PAD_COLS ? PLANT_PAD_COLS : *col);
    *row = *row < 0.0 ? 0.0 : (*row > PLANT_PAD_ROWS ? PLANT_PAD_ROWS : *row);
}

/* The footprint of a pad's contacts: the rectangle of cells spanned by the
 * contact points (the engine puts them at the corners of the touching
 * area), its force spread evenly over it. */
typedef struct {
    double row_lo, row_hi, col_lo, col_hi;
    bool any;
} footprint_t;

static void footprint_add(const mujoco_plant_t *p, unsigned pad, const double *pos, footprint_t *fp)
{
    const mjModel *m = p->m;
    int g = p->pad_geom[pad];
    const double *c = &p->d->geom_xpos[3 * g];
    const double *r = &p->d->geom_xmat[9 * g];
    double rel[3] = {pos[0] - c[0], pos[1] - c[1], pos[2] - c[2]};
    double local[3];
    for (int k = 0; k < 3; k++) { /* R^T * rel */
        local[k] = r[k] * rel[0] + r[3 + k] * rel[1] + r[6 + k] * rel[2];
    }
    double row, col;
    cell_of(m, g, local, &row, &col);
    if (!fp->any) {
        *fp = (footprint_t){row, row, col, col, true};
        return;
    }
    fp->row_lo = row < fp->row_lo ? row : fp->row_lo;
    fp->row_hi = row > fp->row_hi ? row : fp->row_hi;
    fp->col_lo = col < fp->col_lo ? col : fp->col_lo;
    fp->col_hi = col > fp->col_hi ? col : fp->col_hi;
}

/* The cells whose area the footprint covers (a point covers its cell). */
static void spread(const footprint_t *fp, float force_n, float *cells)
{
    memset(cells, 0, sizeof(float) * PLANT_PAD_CELLS);
    if (!fp->any || force_n <= 0.0f) {
        return;
    }
    unsigned r0 = (unsigned)fp->row_lo, c0 = (unsigned)fp->col_lo;
    unsigned r1 = (unsigned)ceil(fp->row_hi), c1 = (unsigned)ceil(fp->col_hi);
    r0 = r0 >= PLANT_PAD_ROWS ? PLANT_PAD_ROWS - 1u : r0;
    c0 = c0 >= PLANT_PAD_COLS ? PLANT_PAD_COLS - 1u : c0;
    r1 = r1 <= r0 ? r0 + 1u : r1;
    c1 = c1 <= c0 ? c0 + 1u : c1;
    float share = force_n / (float)((r1 - r0) * (c1 - c0));
    for (unsigned r = r0; r < r1; r++) {
        for (unsigned c = c0; c < c1; c++) {
            cells[r * PLANT_PAD_COLS + c] = share;
        }
    }
}

static void read_pads(const mujoco_plant_t *p, plant_sample_t *out)
{
    footprint_t fp[PLANT_FINGERS] = {{0}};
    for (int i = 0; i < p->d->ncon; i++) {
        const mjContact *con = &p->d->contact[i];
        for (unsigned pad = 0; pad < PLANT_FINGERS; pad++) {
            if (con->geom1 == p->pad_geom[pad] || con->geom2 == p->pad_geom[pad]) {
                footprint_add(p, pad, con->pos, &fp[pad]);
            }
        }
    }
    for (unsigned pad = 0; pad < PLANT_FINGERS; pad++) {
        float force = (float)p->d->sensordata[p->pad_sensor[pad]];
        out->pad[pad].force_n = force > 0.0f ? force : 0.0f;
        spread(&fp[pad], out->pad[pad].force_n, out->pad[pad].cells_n);
    }
}

static void mujoco_step(void *ctx, const plant_drive_t *drive, uint32_t dt_us, plant_sample_t *out)
{
    mujoco_plant_t *p = ctx;
    command_drive(p, drive);
    bool quiet = true;
    for (uint32_t t = 0; t < dt_us; t += p->timestep_us) {
        move_base(p);
        physics_mj.mj_step(p->m, p->d);
        quiet = quiet && all_quiet(p);
    }
    p->time_us += dt_us;
    out->time_us = p->time_us;
    out->width_mm = (float)(p->d->actuator_length[p->motor] * 1e3);
    out->velocity_mm_s = (float)(p->d->actuator_velocity[p->motor] * 1e3);
    out->motor_force_n = (float)p->d->actuator_force[p->motor];
    read_pads(p, out);
    out->jaw_force_n = 0.5f * (out->pad[0].force_n + out->pad[1].force_n);
    out->quiet = quiet;
}

static unsigned mujoco_body_count(void *ctx)
{
    return (unsigned)((const mujoco_plant_t *)ctx)->m->nbody;
}

/* The first geom of a body that collides, -1 when none does. */
static int colliding_geom(const mjModel *m, int body)
{
    for (int g = m->body_geomadr[body]; g >= 0 && g < m->body_geomadr[body] + m->body_geomnum[body];
         g++) {
        if (m->geom_contype[g] != 0 || m->geom_conaffinity[g] != 0) {
            return g;
        }
    }
    return -1;
}

static bool is_free(const mjModel *m, int body)
{
    int j = m->body_jntadr[body];
    return j >= 0 && m->body_jntnum[body] == 1 && m->jnt_type[j] == mjJNT_FREE;
}

static bool mujoco_body(void *ctx, unsigned index, plant_body_t *out)
{
    const mujoco_plant_t *p = ctx;
    const mjModel *m = p->m;
    if (index >= (unsigned)m->nbody) {
        return false;
    }
    int b = (int)index;
    const char *name = physics_mj.mj_id2name(m, mjOBJ_BODY, b);
    snprintf(out->name, sizeof(out->name), "%s", name != NULL ? name : "");
    memcpy(out->pos_m, &p->d->xpos[3 * b], sizeof(out->pos_m));
    memcpy(out->quat, &p->d->xquat[4 * b], sizeof(out->quat));
    out->free = is_free(m, b);
    out->mocap = m->body_mocapid[b] >= 0;
    memset(out->vel_m_s, 0, sizeof(out->vel_m_s));
    if (out->free) {
        memcpy(out->vel_m_s, &p->d->qvel[m->jnt_dofadr[m->body_jntadr[b]]], sizeof(out->vel_m_s));
    } else if (out->mocap && m->body_mocapid[b] == p->base_mocap) {
        memcpy(out->vel_m_s, p->mocap_vel, sizeof(out->vel_m_s));
    }
    out->mass_kg = m->body_mass[b];
    int g = colliding_geom(m, b);
    out->friction = g >= 0 ? m->geom_friction[3 * g] : 0.0;
    return true;
}

static unsigned mujoco_contacts(void *ctx, plant_contact_t *out, unsigned cap)
{
    const mujoco_plant_t *p = ctx;
    unsigned n = (unsigned)p->d->ncon;
    for (unsigned i = 0; i < n && i < cap; i++) {
        const mjContact *con = &p->d->contact[i];
        mjtNum f[6];
        physics_mj.mj_contactForce(p->m, p->d, (int)i, f);
        out[i].body[0] = (unsigned)p->m->geom_bodyid[con->geom1];
        out[i].body[1] = (unsigned)p->m->geom_bodyid[con->geom2];
        memcpy(out[i].pos_m, con->pos, sizeof(out[i].pos_m));
        memcpy(out[i].normal, con->frame, sizeof(out[i].normal));
        out[i].normal_n = f[0] > 0.0 ? f[0] : 0.0;
        out[i].tangent_n = sqrt(f[1] * f[1] + f[2] * f[2]);
    }
    return n;
}

/* What a scene change may set: beyond these the engine's integration
 * breaks down (it resets the scene itself) rather than model anything. */
#define POSITION_MAX_M 10.0
#define SPEED_MAX_M_S 10.0
#define FORCE_MAX_N 10000.0

/* Three finite numbers, none beyond limit. */
static bool within3(const double *v, double limit)
{
    for (int k = 0; k < 3; k++) {
        if (!(fabs(v[k]) <= limit)) {
            return false;
        }
    }
    return true;
}

/* A free body placed or set moving; the mocap base moved or set moving. */
static plant_err_t set_motion(mujoco_plant_t *p, int b, plant_set_t what, const double *value)
{
    const mjModel *m = p->m;
    if (!within3(value, what == PLANT_SET_POSITION ? POSITION_MAX_M : SPEED_MAX_M_S)) {
        return PLANT_ERR_VALUE;
    }
    if (is_free(m, b)) {
        int j = m->body_jntadr[b];
        double *target = what == PLANT_SET_POSITION ? &p->d->qpos[m->jnt_qposadr[j]]
                                                    : &p->d->qvel[m->jnt_dofadr[j]];
        memcpy(target, value, 3 * sizeof(double));
        if (what == PLANT_SET_POSITION) { /* at rest there, upright */
            memset(&p->d->qvel[m->jnt_dofadr[j]], 0, 6 * sizeof(double));
            double upright[4] = {1.0, 0.0, 0.0, 0.0};
            memcpy(&p->d->qpos[m->jnt_qposadr[j] + 3], upright, sizeof(upright));
        }
    } else if (m->body_mocapid[b] >= 0 && m->body_mocapid[b] == p->base_mocap) {
        double *target =
            what == PLANT_SET_POSITION ? &p->d->mocap_pos[3 * p->base_mocap] : p->mocap_vel;
        memcpy(target, value, 3 * sizeof(double));
    } else {
        return PLANT_ERR_FIXED;
    }
    physics_mj.mj_forward(p->m, p->d);
    return PLANT_OK;
}

static plant_err_t set_mass(mujoco_plant_t *p, int b, double kg)
{
    mjModel *m = p->m;
    if (!is_free(m, b)) {
        return PLANT_ERR_FIXED;
    }
    if (!isfinite(kg) || kg <= 0.0 || kg > 1e4 || m->body_mass[b] <= 0.0) {
        return PLANT_ERR_VALUE;
    }
    double scale = kg / m->body_mass[b];
    m->body_mass[b] = kg;
    for (int k = 0; k < 3; k++) {
        m->body_inertia[3 * b + k] *= scale;
    }
    return PLANT_OK;
}

static plant_err_t set_friction(mujoco_plant_t *p, int b, double mu)
{
    mjModel *m = p->m;
    if (!isfinite(mu) || mu < 0.0 || mu > 10.0) {
        return PLANT_ERR_VALUE;
    }
    if (colliding_geom(m, b) < 0) {
        return PLANT_ERR_FIXED;
    }
    for (int g = m->body_geomadr[b]; g < m->body_geomadr[b] + m->body_geomnum[b]; g++) {
        m->geom_friction[3 * g] = mu;
    }
    return PLANT_OK;
}

static plant_err_t mujoco_set(void *ctx, unsigned index, plant_set_t what, const double *value)
{
    mujoco_plant_t *p = ctx;
    if (index == 0u || index >= (unsigned)p->m->nbody) {
        return index == 0u ? PLANT_ERR_FIXED : PLANT_ERR_NO_BODY;
    }
    int b = (int)index;
    switch (what) {
    case PLANT_SET_POSITION:
    case PLANT_SET_VELOCITY:
        return set_motion(p, b, what, value);
    case PLANT_SET_FORCE:
        if (!is_free(p->m, b)) {
            return PLANT_ERR_FIXED;
        }
        if (!within3(value, FORCE_MAX_N)) {
            return PLANT_ERR_VALUE;
        }
        memcpy(&p->d->xfrc_applied[6 * b], value, 3 * sizeof(double));
        return PLANT_OK;
    case PLANT_SET_MASS:
        return set_mass(p, b, value[0]);
    case PLANT_SET_FRICTION:
        return set_friction(p, b, value[0]);
    default:
        return PLANT_ERR_UNSUPPORTED;
    }
}

static void mujoco_destroy(void *ctx)
{
    mujoco_plant_t *p = ctx;
    physics_mj.mj_deleteData(p->d);
    physics_mj.mj_deleteModel(p->m);
    physics_mj.mj_deleteModel(p->loaded);
    free(p);
}

static const plant_ops_t mujoco_ops = {
    .name = "mujoco",
    .timestep_us = mujoco_timestep_us,
    .step = mujoco_step,
    .reset = mujoco_reset,
    .body_count = mujoco_body_count,
    .body = mujoco_body,
    .contacts = mujoco_contacts,
    .set = mujoco_set,
    .destroy = mujoco_destroy,
};

bool physics_mujoco_open(plant_t *plant, const char *model_dir, const char *scene_file,
                         float stroke_mm, float width_mm, char *why, size_t cap)
{
    if (!physics_mujoco_load(why, cap)) {
        return false;
    }
    *physics_mj.mju_user_warning = log_warning;
    *physics_mj.mju_user_error = fatal_error;
    char gripper[4096], scene[4096];
    snprintf(gripper, sizeof(gripper), "%s/%s", model_dir, PHYSICS_GRIPPER_FILE);
    if (scene_file == NULL) {
        snprintf(scene, sizeof(scene), "%s/%s", model_dir, PHYSICS_DEFAULT_SCENE_FILE);
    } else if (realpath(scene_file, scene) == NULL) {
        snprintf(why, cap, "%s: no such file", scene_file);
        return false;
    }
    if (!regular_file(gripper, why, cap) || !regular_file(scene, why, cap)) {
        return false;
    }
    mujoco_plant_t *p = calloc(1, sizeof(*p));
    if (p == NULL) {
        snprintf(why, cap, "out of memory");
        return false;
    }
    if (!load_model(p, gripper, scene, why, cap) || !find_parts(p, why, cap) ||
        (p->d = physics_mj.mj_makeData(p->m)) == NULL) {
        physics_mj.mj_deleteModel(p->m);
        free(p);
        return false;
    }
    set_stroke(p, stroke_mm);
    p->loaded = physics_mj.mj_copyModel(NULL, p->m);
    if (p->loaded == NULL) {
        mujoco_destroy(p);
        snprintf(why, cap, "out of memory");
        return false;
    }
    mujoco_reset(p, width_mm);
    plant->ops = &mujoco_ops;
    plant->ctx = p;
    return true;
}
