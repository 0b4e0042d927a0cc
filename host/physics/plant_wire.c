/* SPDX-License-Identifier: BSD-3-Clause */
#include "plant_wire.h"

#include <math.h>
#include <string.h>

static const uint8_t magic[4] = {'W', 'S', 'G', 'P'};
/* No reading or pose of a gripper's scene comes near this (mm, N, m, kg):
 * a number beyond it is garbage, and would overflow when converted. */
#define NUMBER_MAX 1e9

void plant_wire_put_u32(uint8_t *at, uint32_t v)
{
    for (unsigned i = 0; i < 4u; i++) {
        at[i] = (uint8_t)(v >> (8u * i));
    }
}

static void put_u64(uint8_t *at, uint64_t v)
{
    for (unsigned i = 0; i < 8u; i++) {
        at[i] = (uint8_t)(v >> (8u * i));
    }
}

void plant_wire_put_f32(uint8_t *at, float v)
{
    uint32_t bits;
    memcpy(&bits, &v, sizeof(bits));
    plant_wire_put_u32(at, bits);
}

void plant_wire_put_f64(uint8_t *at, double v)
{
    uint64_t bits;
    memcpy(&bits, &v, sizeof(bits));
    put_u64(at, bits);
}

static uint32_t get_u32(const uint8_t *at)
{
    return (uint32_t)at[0] | (uint32_t)at[1] << 8 | (uint32_t)at[2] << 16 | (uint32_t)at[3] << 24;
}

static uint64_t get_u64(const uint8_t *at)
{
    return (uint64_t)get_u32(at) | (uint64_t)get_u32(at + 4) << 32;
}

static float get_f32(const uint8_t *at)
{
    uint32_t bits = get_u32(at);
    float v;
    memcpy(&v, &bits, sizeof(v));
    return v;
}

static double get_f64(const uint8_t *at)
{
    uint64_t bits = get_u64(at);
    double v;
    memcpy(&v, &bits, sizeof(v));
    return v;
}

size_t plant_wire_request(uint8_t *out, plant_msg_t type, const uint8_t *payload, size_t len)
{
    memcpy(out, magic, sizeof(magic));
    out[4] = PLANT_WIRE_VERSION;
    out[5] = (uint8_t)type;
    out[6] = 0u;
    out[7] = 0u;
    plant_wire_put_u32(out + 8, (uint32_t)len);
    if (len > 0u) {
        memcpy(out + PLANT_WIRE_HEADER, payload, len);
    }
    return PLANT_WIRE_HEADER + len;
}

void plant_wire_step_payload(uint8_t out[PLANT_WIRE_STEP_REQ], const plant_drive_t *drive,
                             uint32_t dt_us)
{
    plant_wire_put_u32(out, dt_us);
    plant_wire_put_u32(out + 4, drive->enabled ? 1u : 0u);
    plant_wire_put_f32(out + 8, drive->position_mm);
    plant_wire_put_f32(out + 12, drive->velocity_mm_s);
    plant_wire_put_f32(out + 16, drive->force_limit_n);
}

void plant_wire_set_payload(uint8_t out[PLANT_WIRE_SET_REQ], unsigned index, plant_set_t what,
                            const double *value)
{
    unsigned count = what == PLANT_SET_MASS || what == PLANT_SET_FRICTION ? 1u : 3u;
    plant_wire_put_u32(out, index);
    plant_wire_put_u32(out + 4, (uint32_t)what);
    for (unsigned i = 0; i < 3u; i++) {
        plant_wire_put_f64(out + 8 + 8u * i, i < count ? value[i] : 0.0);
    }
}

/* The payload a successful reply to type carries; 0 for a variable one. */
static uint32_t fixed_length(plant_msg_t type)
{
    switch (type) {
    case PLANT_MSG_HELLO:
        return PLANT_WIRE_HELLO_REPLY;
    case PLANT_MSG_STEP:
        return PLANT_WIRE_SAMPLE;
    case PLANT_MSG_BODIES:
        return PLANT_WIRE_BODIES_REPLY;
    case PLANT_MSG_BODY:
        return PLANT_WIRE_BODY_REPLY;
    default:
        return 0u;
    }
}

const char *plant_wire_header(const uint8_t in[PLANT_WIRE_HEADER], plant_msg_t type,
                              plant_wire_header_t *out)
{
    if (memcmp(in, magic, sizeof(magic)) != 0) {
        return "not a plant protocol reply (bad magic)";
    }
    out->version = in[4];
    out->type = in[5];
    out->status = (uint16_t)(in[6] | in[7] << 8);
    out->length = get_u32(in + 8);
    if (out->version != PLANT_WIRE_VERSION) {
        return "the plant speaks another protocol version";
    }
    if (out->type != (uint8_t)type) {
        return "a reply to another request";
    }
    if (out->status > PLANT_ERR_UNSUPPORTED) {
        return "an unknown status";
    }
    bool may_fail = type != PLANT_MSG_HELLO && type != PLANT_MSG_RESET && type != PLANT_MSG_STEP;
    if (out->status != PLANT_OK) {
        return !may_fail ? "the plant refused a step" : (out->length != 0u ? "bad length" : NULL);
    }
    if (type == PLANT_MSG_CONTACTS) {
        bool fits = out->length >= 8u && out->length <= PLANT_WIRE_PAYLOAD_MAX &&
                    (out->length - 8u) % PLANT_WIRE_CONTACT == 0u;
        return fits ? NULL : "bad length";
    }
    return out->length == fixed_length(type) ? NULL : "bad length";
}

const char *plant_wire_hello(const uint8_t *in, size_t len, plant_wire_hello_t *out)
{
    if (len != PLANT_WIRE_HELLO_REPLY) {
        return "bad length";
    }
    out->timestep_us = get_u32(in);
    out->features = get_u32(in + 4);
    memcpy(out->name, in + 8, PLANT_WIRE_NAME_MAX);
    out->name[PLANT_WIRE_NAME_MAX] = '\0';
    for (char *c = out->name; *c != '\0'; c++) {
        if (*c < ' ' || *c > '~') {
            return "the plant's name is not printable";
        }
    }
    return NULL;
}

/* n floats from in: false when one is not finite (or negative, if not
 * signed). */
static bool get_floats(const uint8_t *in, float *out, size_t n, bool signed_ok)
{
    for (size_t i = 0; i < n; i++) {
        out[i] = get_f32(in + 4u * i);
        if (!(fabsf(out[i]) <= (float)NUMBER_MAX) || (!signed_ok && out[i] < 0.0f)) {
            return false;
        }
    }
    return true;
}

const char *plant_wire_sample(const uint8_t *in, size_t len, plant_sample_t *out)
{
    if (len != PLANT_WIRE_SAMPLE) {
        return "bad length";
    }
    float jaw[4];
    out->time_us = get_u64(in);
    bool ok = get_floats(in + 8, jaw, 4u, true);
    out->width_mm = jaw[0];
    out->velocity_mm_s = jaw[1];
    out->motor_force_n = jaw[2];
    out->jaw_force_n = jaw[3];
    out->quiet = get_u32(in + 24) != 0u;
    for (unsigned f = 0; f < PLANT_FINGERS; f++) {
        const uint8_t *pad = in + 28u + f * PLANT_WIRE_PAD;
        ok = ok && get_floats(pad, &out->pad[f].force_n, 1u, false) &&
             get_floats(pad + 4, out->pad[f].cells_n, PLANT_PAD_CELLS, false);
    }
    return ok ? NULL : "a reading out of range (or a negative force)";
}

const char *plant_wire_bodies(const uint8_t *in, size_t len, unsigned *count)
{
    if (len != PLANT_WIRE_BODIES_REPLY) {
        return "bad length";
    }
    uint32_t n = get_u32(in);
    *count = n > 1000u ? 0u : (unsigned)n;
    return n > 1000u ? "more than 1000 bodies" : NULL;
}

static bool get_doubles(const uint8_t *in, double *out, size_t n)
{
    for (size_t i = 0; i < n; i++) {
        out[i] = get_f64(in + 8u * i);
        if (!(fabs(out[i]) <= NUMBER_MAX)) {
            return false;
        }
    }
    return true;
}

const char *plant_wire_body(const uint8_t *in, size_t len, plant_body_t *out)
{
    if (len != PLANT_WIRE_BODY_REPLY) {
        return "bad length";
    }
    memcpy(out->name, in, PLANT_NAME_MAX);
    out->name[PLANT_NAME_MAX - 1u] = '\0';
    for (const char *c = out->name; *c != '\0'; c++) {
        if (*c <= ' ' || *c > '~' || *c == '"' || *c == '\\' || *c == ',') {
            return "a body's name is not a plain word";
        }
    }
    const uint8_t *at = in + PLANT_NAME_MAX;
    bool ok = get_doubles(at, out->pos_m, 3u) && get_doubles(at + 24, out->quat, 4u) &&
              get_doubles(at + 56, out->vel_m_s, 3u) && get_doubles(at + 80, &out->mass_kg, 1u) &&
              get_doubles(at + 88, &out->friction, 1u);
    uint32_t flags = get_u32(at + 96);
    out->free = (flags & 1u) != 0u;
    out->mocap = (flags & 2u) != 0u;
    return ok ? NULL : "a body's number out of range";
}

const char *plant_wire_contacts(const uint8_t *in, size_t len, plant_contact_t *out, unsigned cap,
                                unsigned *total)
{
    if (len < 8u || (len - 8u) % PLANT_WIRE_CONTACT != 0u) {
        return "bad length";
    }
    uint32_t all = get_u32(in);
    uint32_t n = get_u32(in + 4);
    if (n != (len - 8u) / PLANT_WIRE_CONTACT || n > cap || all < n) {
        return "a contact count that does not fit";
    }
    for (uint32_t i = 0; i < n; i++) {
        const uint8_t *at = in + 8u + i * PLANT_WIRE_CONTACT;
        plant_contact_t *c = &out[i];
        c->body[0] = get_u32(at);
        c->body[1] = get_u32(at + 4);
        if (!get_doubles(at + 8, c->pos_m, 3u) || !get_doubles(at + 32, c->normal, 3u) ||
            !get_doubles(at + 56, &c->normal_n, 1u) || !get_doubles(at + 64, &c->tangent_n, 1u)) {
            return "a contact's number out of range";
        }
    }
    *total = all;
    return NULL;
}
