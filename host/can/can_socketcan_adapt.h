/* SPDX-License-Identifier: BSD-3-Clause */
/* The Linux-specific half of the SocketCAN driver (after Zephyr's
 * can_native_linux_adapt.c): the only file that includes Linux CAN headers.
 * Plain descriptors and hal_can_frame_t cross the boundary. */
#ifndef CAN_SOCKETCAN_ADAPT_H
#define CAN_SOCKETCAN_ADAPT_H

#include <stddef.h>

#include "hal_can.h"

/* A non-blocking CAN_RAW socket bound to ifname; -1 with a message in err. */
int can_adapt_open(const char *ifname, char *err, size_t err_len);
/* 0, or a negative errno (-EAGAIN/-ENOBUFS when the queue is full). */
int can_adapt_send(int fd, const hal_can_frame_t *frame);
/* 1 with a frame, 0 when none is waiting, or a negative errno. */
int can_adapt_recv(int fd, hal_can_frame_t *frame);
/* CAN_RAW_FILTER; count 0 accepts everything. 0 or a negative errno. */
int can_adapt_set_filters(int fd, const hal_can_filter_t *filters, unsigned count);
void can_adapt_close(int fd);

#endif
