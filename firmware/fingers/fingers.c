/* SPDX-License-Identifier: BSD-3-Clause */
#include "wsg/wsg_fingers.h"

#include <string.h>

#define FINGER_FAULT_MASK                                                                          \
    (WSG_FLAG(FF_POWER_FAULT) | WSG_FLAG(FF_COMM_FAULT) | WSG_FLAG(FF_INIT_FAULT))

void wsg_fingers_reset(wsg_fingers_t *fingers)
{
    memset(fingers, 0, sizeof(*fingers));
}

const char *wsg_finger_type_name(wsg_finger_type_t type)
{
    switch (type) {
    case FINGER_GENERIC:
        return "generic";
    case FINGER_FMF:
        return "fmf";
    case FINGER_DSA:
        return "dsa";
    case FINGER_NONE:
    default:
        return "none";
    }
}

bool wsg_finger_has_data(const wsg_finger_t *finger)
{
    return finger->data_count > 0;
}

bool wsg_fingers_faulted(const wsg_fingers_t *fingers)
{
    for (unsigned i = 0; i < WSG_FINGER_COUNT; i++) {
        if ((fingers->slot[i].flags & FINGER_FAULT_MASK) != 0u) {
            return true;
        }
    }
    return false;
}

bool wsg_fingers_force_control(const wsg_fingers_t *fingers)
{
    for (unsigned i = 0; i < WSG_FINGER_COUNT; i++) {
        if (fingers->slot[i].type == FINGER_FMF && wsg_finger_has_data(&fingers->slot[i])) {
            return true;
        }
    }
    return false;
}

float wsg_fingers_measured_force(const wsg_fingers_t *fingers)
{
    float sum = 0.0f;
    unsigned count = 0;
    for (unsigned i = 0; i < WSG_FINGER_COUNT; i++) {
        const wsg_finger_t *f = &fingers->slot[i];
        if (f->type == FINGER_FMF && wsg_finger_has_data(f)) {
            sum += f->data[0];
            count++;
        }
    }
    return count > 0u ? sum / (float)count : 0.0f;
}

wsg_status_t wsg_fingers_tare(wsg_fingers_t *fingers, int index)
{
    bool found = false;
    for (int i = 0; i < WSG_FINGER_COUNT; i++) {
        const wsg_finger_t *f = &fingers->slot[i];
        if ((index < 0 || index == i) && f->type == FINGER_FMF && wsg_finger_has_data(f)) {
            found = true;
        }
    }
    return found ? E_SUCCESS : E_NOT_AVAILABLE;
}
