/* SPDX-License-Identifier: BSD-3-Clause */
/* SocketCAN through Linux headers (can_socketcan_adapt.h). */
#include "can_socketcan_adapt.h"

#include <errno.h>
#include <fcntl.h>
#include <linux/can.h>
#include <linux/can/raw.h>
#include <net/if.h>
#include <stdio.h>
#include <string.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <unistd.h>

/* Room for a busy finger bus (~600 frames/s, ~1 KiB of kernel memory each)
 * while the process is descheduled: about a second asked, but the kernel
 * caps it at net.core.rmem_max (about 0.4 s of frames with Linux's default
 * limit); more needs that sysctl raised. */
#define CAN_ADAPT_RCVBUF_BYTES (1024 * 1024)

int can_adapt_open(const char *ifname, char *err, size_t err_len)
{
    if (strlen(ifname) >= IFNAMSIZ) {
        snprintf(err, err_len, "interface name '%s' is too long", ifname);
        return -1;
    }
    int fd = socket(PF_CAN, SOCK_RAW | SOCK_NONBLOCK | SOCK_CLOEXEC, CAN_RAW);
    if (fd < 0) {
        snprintf(err, err_len, "socket(PF_CAN): %s%s", strerror(errno),
                 errno == EAFNOSUPPORT ? " (this kernel has no SocketCAN)" : "");
        return -1;
    }
    struct ifreq ifr;
    memset(&ifr, 0, sizeof(ifr));
    memcpy(ifr.ifr_name, ifname, strlen(ifname) + 1);
    if (ioctl(fd, SIOCGIFINDEX, &ifr) < 0) {
        snprintf(err, err_len, "CAN interface '%s': %s", ifname, strerror(errno));
        close(fd);
        return -1;
    }
    struct sockaddr_can addr;
    memset(&addr, 0, sizeof(addr));
    addr.can_family = AF_CAN;
    addr.can_ifindex = ifr.ifr_ifindex;
    if (bind(fd, (struct sockaddr *)&addr, sizeof(addr)) < 0) {
        snprintf(err, err_len, "bind to '%s': %s", ifname, strerror(errno));
        close(fd);
        return -1;
    }
    int rcvbuf = CAN_ADAPT_RCVBUF_BYTES;
    (void)setsockopt(fd, SOL_SOCKET, SO_RCVBUF, &rcvbuf, sizeof(rcvbuf)); /* best effort */
    return fd;
}

static canid_t to_canid(uint32_t id, uint8_t flags)
{
    canid_t out = (flags & HAL_CAN_FLAG_EXT) != 0u ? ((id & CAN_EFF_MASK) | CAN_EFF_FLAG)
                                                   : (id & CAN_SFF_MASK);
    return (flags & HAL_CAN_FLAG_RTR) != 0u ? (out | CAN_RTR_FLAG) : out;
}

int can_adapt_send(int fd, const hal_can_frame_t *frame)
{
    struct can_frame cf;
    memset(&cf, 0, sizeof(cf));
    cf.can_id = to_canid(frame->id, frame->flags);
    cf.len = frame->dlc > CAN_MAX_DLEN ? CAN_MAX_DLEN : frame->dlc;
    memcpy(cf.data, frame->data, cf.len);
    ssize_t n = write(fd, &cf, sizeof(cf));
    if (n == (ssize_t)sizeof(cf)) {
        return 0;
    }
    return n < 0 ? -errno : -EIO;
}

int can_adapt_recv(int fd, hal_can_frame_t *frame)
{
    struct can_frame cf;
    for (;;) {
        ssize_t n = read(fd, &cf, sizeof(cf));
        if (n < 0) {
            return (errno == EAGAIN || errno == EWOULDBLOCK) ? 0 : -errno;
        }
        if (n == (ssize_t)sizeof(cf) && (cf.can_id & CAN_ERR_FLAG) == 0u) {
            break; /* skip error frames and anything that is not a classic frame */
        }
    }
    memset(frame, 0, sizeof(*frame));
    bool ext = (cf.can_id & CAN_EFF_FLAG) != 0u;
    frame->id = ext ? (cf.can_id & CAN_EFF_MASK) : (cf.can_id & CAN_SFF_MASK);
    frame->flags = (uint8_t)((ext ? HAL_CAN_FLAG_EXT : 0u) |
                             ((cf.can_id & CAN_RTR_FLAG) != 0u ? HAL_CAN_FLAG_RTR : 0u));
    frame->dlc = cf.len > CAN_MAX_DLEN ? CAN_MAX_DLEN : cf.len;
    memcpy(frame->data, cf.data, frame->dlc);
    return 1;
}

int can_adapt_set_filters(int fd, const hal_can_filter_t *filters, unsigned count)
{
    struct can_filter rf[HAL_CAN_MAX_FILTERS];
    if (count > HAL_CAN_MAX_FILTERS) {
        return -EINVAL;
    }
    for (unsigned i = 0; i < count; i++) {
        rf[i].can_id = to_canid(filters[i].id, filters[i].flags);
        rf[i].can_mask = (filters[i].mask & CAN_EFF_MASK) | CAN_EFF_FLAG | CAN_RTR_FLAG;
        rf[i].can_id &= ~CAN_RTR_FLAG;
    }
    if (count == 0u) {
        rf[0].can_id = 0;
        rf[0].can_mask = 0;
        count = 1;
    }
    socklen_t len = (socklen_t)(count * sizeof(rf[0]));
    return setsockopt(fd, SOL_CAN_RAW, CAN_RAW_FILTER, rf, len) < 0 ? -errno : 0;
}

void can_adapt_close(int fd)
{
    if (fd >= 0) {
        close(fd);
    }
}
