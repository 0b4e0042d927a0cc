/* SPDX-License-Identifier: BSD-3-Clause */
/* wsgproxy: a transparent recording proxy between a WSG driver and a
 * gripper (docs/calibration.md, "Record through the proxy"). The driver
 * talks to the proxy's ports as it would to the gripper; every byte goes on
 * unchanged, and the record (wsgsim's record format, docs/simctl.md) gets
 * each GCL line and binary frame both ways with its time. One thread, one
 * epoll loop (host/os/loop). */
#ifndef WSGPROXY_PROXY_H
#define WSGPROXY_PROXY_H

#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <sys/socket.h>

#include "loop.h"
#include "net.h"
#include "split.h"

#define PROXY_UDP_PEERS 64 /* the least recently heard is forgotten beyond */
/* The record is written out this long after its first unwritten line (and
 * whenever stdio's buffer fills, and at exit): a write per wake-up would
 * put the file system on the way of the next request. */
#define PROXY_FLUSH_NS 200000000ull

typedef struct {
    const char *listen;  /* the proxy's address for the driver */
    const char *gripper; /* the gripper's address */
    int tcp_port, gripper_tcp_port;
    int udp_port, gripper_udp_port; /* GCL over UDP; -1: off */
    int bin_port, gripper_bin_port; /* binary over UDP; -1: off */
    int bin_reply_port;             /* the driver's reply port; 0: its source port */
    int gripper_bin_reply_port;     /* where the gripper replies; 0: the sending port */
    const char *record_path;
    const char *ready_file;
} proxy_options_t;

typedef enum { UDP_GCL, UDP_BINARY } udp_kind_t;

/* One driver address heard on a UDP port, and the proxy's socket that
 * speaks for it to the gripper. */
typedef struct {
    struct proxy *owner;
    bool used;
    udp_kind_t kind;
    struct sockaddr_storage driver;
    socklen_t driver_len;
    int upstream;
    uint64_t id, last_heard_ns;
    char channel[24];
} udp_peer_t;

typedef struct proxy {
    proxy_options_t opt;
    host_loop_t *loop;
    net_t net;
    FILE *record;
    bool record_dirty; /* lines not yet written out */
    uint64_t flush_ns; /* and when they will be (CLOCK_MONOTONIC) */
    uint64_t start_ns;
    uint64_t next_id; /* sessions and UDP peers share the numbering */
    struct sockaddr_storage gripper;
    socklen_t gripper_len;
    int tcp_listener, udp_gcl, udp_bin, udp_bin_replies;
    udp_peer_t peers[PROXY_UDP_PEERS];
    udp_peer_t *last_binary; /* the gripper's binary replies on its reply port go to it */
    splitter_t datagram;     /* cuts one datagram into lines (reused) */
} proxy_t;

/* The record's clock: seconds since the proxy started, in µs. */
uint64_t proxy_now_us(const proxy_t *p);
/* Feeds `len` bytes of one direction of a channel ('>' from the driver,
 * '<' to it) to its splitter and records each unit they complete, at
 * `at_us`; flush: and what is left. */
void proxy_record(proxy_t *p, splitter_t *split, const char *channel, char direction,
                  const unsigned char *data, size_t len, uint64_t at_us, bool flush);
/* A line on stderr, "wsgproxy: " before it. */
void proxy_log(const char *fmt, ...) __attribute__((format(printf, 1, 2)));
/* A line of the record starting with '#': what happened to a channel. */
void proxy_note(proxy_t *p, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
/* Sets an IPv4 or IPv6 address's port. */
void proxy_set_port(struct sockaddr_storage *ss, int port);
/* The gripper's address at another port. */
struct sockaddr_storage proxy_gripper_at(const proxy_t *p, int port);

bool proxy_tcp_start(proxy_t *p);
bool proxy_udp_start(proxy_t *p);
void proxy_udp_stop(proxy_t *p);

#endif
