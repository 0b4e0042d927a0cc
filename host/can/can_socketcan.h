/* SPDX-License-Identifier: BSD-3-Clause */
/* A hal_can_t on a SocketCAN interface (vcan0, can0): received frames are
 * drained into a ring when the descriptor is readable and handed out by
 * hal_can_recv(). The Linux specifics live in can_socketcan_adapt.c. */
#ifndef CAN_SOCKETCAN_H
#define CAN_SOCKETCAN_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "hal_can.h"

#define CAN_SOCKETCAN_RING 1024u

typedef struct {
    int fd;
    hal_can_t can;
    hal_can_frame_t ring[CAN_SOCKETCAN_RING];
    unsigned head, count;
    uint32_t tx_errors; /* sends the socket refused */
    int last_error;     /* negative errno of the last failed operation */
} can_socketcan_t;

/* Opens and binds; false with a message in err. */
bool can_socketcan_open(can_socketcan_t *s, const char *ifname, char *err, size_t err_len);
void can_socketcan_close(can_socketcan_t *s);
const hal_can_t *can_socketcan_bus(can_socketcan_t *s);
int can_socketcan_fd(const can_socketcan_t *s);
/* Reads every waiting frame into the ring (call when the fd is readable). */
void can_socketcan_drain(can_socketcan_t *s);

#endif
