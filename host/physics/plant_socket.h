/* SPDX-License-Identifier: BSD-3-Clause */
/* The plant (plant.h) computed by another process, another engine
 * (Gazebo, Isaac, Bullet, a test's reference plant), over a Unix-domain
 * stream socket in lock-step with the device: docs/physics.md, "Plant
 * protocol". A plant that dies, answers garbage or does not answer within
 * the deadline is a fault: the jaws stand, the device reports a power
 * fault and serves its clients; a reset connects again. */
#ifndef HOST_PLANT_SOCKET_H
#define HOST_PLANT_SOCKET_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "physics_world.h"
#include "plant.h"

/* Connects to the plant listening at path and shakes hands (the jaws at
 * width_mm); false with *why. */
bool plant_socket_open(plant_t *plant, const char *path, unsigned timeout_ms, float stroke_mm,
                       float width_mm, char *why, size_t cap);
/* A socket plant's fault: NULL while it answers, else why it is lost. */
const char *plant_socket_fault(const plant_t *plant);
/* A device's world with the plant at path (heap; physics_setup_close()
 * frees it); NULL with *why. */
physics_world_t *plant_socket_world_open(const char *path, unsigned timeout_ms, float stroke_mm,
                                         float emergency_accel_mm_s2, uint64_t now_us, char *why,
                                         size_t cap);

#endif
