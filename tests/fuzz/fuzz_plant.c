/* SPDX-License-Identifier: BSD-3-Clause */
/* libFuzzer target: the replies of a plant process (host/physics/
 * plant_wire.c, docs/physics.md "Plant protocol"), outside input the device
 * reads at every exchange. The input is a run of replies, each a byte that
 * names the request it answers (1..7: HELLO..SET), the 12-byte header and
 * as much payload as the header says (or as is left). What a decoder
 * accepts must hold what the device relies on:
 *   - a sample's readings within +-1e9, the pads' forces and cells >= 0;
 *   - a body's name a printable word, NUL-terminated, its numbers within
 *     +-1e9 (none overflows when scaled to mm);
 *   - no more contacts than asked for, every number within +-1e9;
 *   - a header accepted only with a payload length its type allows. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "plant_wire.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static void require(bool ok, const char *what)
{
    if (!ok) {
        fprintf(stderr, "fuzz_plant: %s\n", what);
        abort();
    }
}

static void check_sample(const uint8_t *in, size_t len)
{
    plant_sample_t s;
    if (plant_wire_sample(in, len, &s) != NULL) {
        return;
    }
    require(fabsf(s.width_mm) <= 1e9f && fabsf(s.velocity_mm_s) <= 1e9f &&
                fabsf(s.motor_force_n) <= 1e9f && fabsf(s.jaw_force_n) <= 1e9f,
            "a sample with a reading out of range");
    for (unsigned f = 0; f < PLANT_FINGERS; f++) {
        require(s.pad[f].force_n >= 0.0f, "a negative pad force");
        for (unsigned c = 0; c < PLANT_PAD_CELLS; c++) {
            require(s.pad[f].cells_n[c] >= 0.0f && s.pad[f].cells_n[c] <= 1e9f, "a bad cell");
        }
    }
}

static void check_body(const uint8_t *in, size_t len)
{
    plant_body_t b;
    if (plant_wire_body(in, len, &b) != NULL) {
        return;
    }
    size_t n = strnlen(b.name, sizeof(b.name));
    require(n < sizeof(b.name), "a body's name without its NUL");
    for (size_t i = 0; i < n; i++) {
        require(b.name[i] > ' ' && b.name[i] <= '~' && b.name[i] != '"', "a body's name");
    }
    const double *numbers[] = {b.pos_m,   b.pos_m + 1, b.pos_m + 2, b.quat,
                               b.vel_m_s, &b.mass_kg,  &b.friction};
    for (size_t i = 0; i < sizeof(numbers) / sizeof(numbers[0]); i++) {
        require(fabs(*numbers[i]) <= 1e9, "a body's number out of range");
    }
}

static void check_contacts(const uint8_t *in, size_t len, unsigned cap)
{
    plant_contact_t c[8];
    unsigned total = 0u;
    if (plant_wire_contacts(in, len, c, cap, &total) != NULL) {
        return;
    }
    unsigned n = (unsigned)((len - 8u) / PLANT_WIRE_CONTACT);
    require(n <= cap && n <= total, "more contacts than asked for");
    for (unsigned i = 0; i < n; i++) {
        require(fabs(c[i].normal_n) <= 1e9 && fabs(c[i].tangent_n) <= 1e9 &&
                    fabs(c[i].pos_m[0]) <= 1e9,
                "a contact's number out of range");
    }
}

static void check_payload(plant_msg_t type, const uint8_t *in, size_t len, unsigned cap)
{
    plant_wire_hello_t hello;
    unsigned count;
    switch (type) {
    case PLANT_MSG_HELLO:
        if (plant_wire_hello(in, len, &hello) == NULL) {
            require(strlen(hello.name) <= PLANT_WIRE_NAME_MAX, "a long name");
        }
        break;
    case PLANT_MSG_STEP:
        check_sample(in, len);
        break;
    case PLANT_MSG_BODIES:
        (void)plant_wire_bodies(in, len, &count);
        break;
    case PLANT_MSG_BODY:
        check_body(in, len);
        break;
    case PLANT_MSG_CONTACTS:
        check_contacts(in, len, cap);
        break;
    default:
        break;
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    size_t at = 0u;
    while (size - at > PLANT_WIRE_HEADER) {
        plant_msg_t type = (plant_msg_t)(data[at] % 7u + 1u);
        unsigned cap = (data[at] >> 3) % 9u; /* contacts asked for: 0..8 */
        at++;
        plant_wire_header_t h;
        const char *why = plant_wire_header(data + at, type, &h);
        at += PLANT_WIRE_HEADER;
        size_t left = size - at;
        size_t len = h.length < left ? h.length : left;
        if (why == NULL) {
            require(h.length <= PLANT_WIRE_PAYLOAD_MAX, "a payload longer than any reply");
            if (h.status == PLANT_OK) {
                check_payload(type, data + at, len, cap);
            }
        }
        at += len;
    }
    return 0;
}
