/* SPDX-License-Identifier: BSD-3-Clause */
/* The fake port's connection: a wsg_conn_t whose output is captured line by
 * line (with its kind and the HAL clock's time), for every Check suite that
 * talks GCL to a device: the device core's (fake_device.h), the finger
 * bus's and the host's simulation control. Public headers only. */
#ifndef FAKE_CONN_H
#define FAKE_CONN_H

#include <check.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "wsg/wsg_conn.h"
#include "wsg/wsg_gcl.h"

#define H_LINES_MAX 4096
#define H_LINE_LEN (WSG_REPLY_MAX + 1)

typedef struct {
    char text[H_LINE_LEN]; /* without its '\n' */
    wsg_msg_kind_t kind;
    uint64_t at_us;
} h_line_t;

typedef struct {
    wsg_conn_t conn;
    h_line_t lines[H_LINES_MAX];
    size_t count;  /* lines captured */
    size_t read;   /* lines consumed by the expect helpers */
    bool bad_line; /* a write that was not exactly one '\n'-terminated line, or overflow */
    /* what the connection did not take while a request of it waited for
     * the processor (a timing profile), fed again at its resume() */
    uint8_t held[1024];
    size_t held_len;
} h_client_t;

/* Opens c on device with drv (NULL: detected from the first byte). */
void h_open_on(h_client_t *c, wsg_device_t *device, const wsg_proto_driver_t *drv,
               wsg_transport_t transport);
void h_close(h_client_t *c, wsg_close_reason_t reason);
void h_send_bytes(h_client_t *c, const void *bytes, size_t len);
void send_line(h_client_t *c, const char *line); /* appends the '\n' */

/* Next unread line ("<no line>" if none), and how many are unread. */
const char *h_next_line(h_client_t *c);
size_t h_unread(const h_client_t *c);
const h_line_t *h_last_read(const h_client_t *c);
/* Sends one line and returns the first line it produced. */
const char *ask(h_client_t *c, const char *line);
/* Reads up to and including the first unread line equal to text; false
 * (all read) when none is. */
bool h_take_line(h_client_t *c, const char *text);
/* Lines captured so far that start with prefix, and drops them all as read. */
size_t h_count_prefix(h_client_t *c, const char *prefix);
void h_discard(h_client_t *c);
/* Forgets every line captured so far: room for H_LINES_MAX more. */
void h_clear(h_client_t *c);

/* Lines the GCL driver counted in on this client's connection. */
uint32_t h_gcl_lines_in(const h_client_t *c);
uint32_t h_gcl_lines_out(const h_client_t *c);

#define expect_line(c, text) ck_assert_str_eq(h_next_line(c), (text))
#define expect_no_line(c) ck_assert_msg(h_unread(c) == 0, "unexpected line \"%s\"", h_next_line(c))

#endif
