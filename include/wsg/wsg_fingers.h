/* SPDX-License-Identifier: BSD-3-Clause */
/* The two finger slots as the core sees them (FTYPE, FFLAGS, FDATA, TARE). */
#ifndef WSG_FINGERS_H
#define WSG_FINGERS_H

#include <stdbool.h>
#include <stdint.h>

#include "wsg_opts.h"
#include "wsg_status.h"
#include "wsg_types.h"

typedef enum { FINGER_NONE, FINGER_GENERIC, FINGER_FMF, FINGER_DSA } wsg_finger_type_t;

typedef struct {
    wsg_finger_type_t type;
    uint16_t flags; /* Appendix C */
    uint16_t data_count;
    float data[WSG_FINGER_DATA_MAX];
} wsg_finger_t;

typedef struct {
    wsg_finger_t slot[WSG_FINGER_COUNT];
} wsg_fingers_t;

void wsg_fingers_reset(wsg_fingers_t *fingers);

/* "none", "generic", "fmf", "dsa" */
const char *wsg_finger_type_name(wsg_finger_type_t type);

bool wsg_finger_has_data(const wsg_finger_t *finger);

/* True when a slot holds a finger in a fault state (SF_FINGER_FAULT). */
bool wsg_fingers_faulted(const wsg_fingers_t *fingers);

/* True when a force-measuring finger can close the force loop (SF_FORCECNTL_MODE). */
bool wsg_fingers_force_control(const wsg_fingers_t *fingers);

/* The force the WSG-FMF fingers measure (their mean); 0 without one. */
float wsg_fingers_measured_force(const wsg_fingers_t *fingers);

/* TARE(): index -1 tares every force finger. E_NOT_AVAILABLE without one
 * that is connected and delivering data. Checks only: wsg_finger_bus_tare() sends. */
wsg_status_t wsg_fingers_tare(wsg_fingers_t *fingers, int index);

#endif
