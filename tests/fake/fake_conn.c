/* SPDX-License-Identifier: BSD-3-Clause */
#include "fake_conn.h"

#include <string.h>

#include "hal_clock.h"

static void write_line(void *ctx, const char *line, size_t len, wsg_msg_kind_t kind)
{
    h_client_t *c = ctx;
    bool one_line =
        len > 0 && line[len - 1] == '\n' && memchr(line, '\n', len - 1) == NULL && len < H_LINE_LEN;
    if (!one_line || c->count == H_LINES_MAX) {
        c->bad_line = true;
        return;
    }
    h_line_t *out = &c->lines[c->count++];
    memcpy(out->text, line, len - 1);
    out->text[len - 1] = '\0';
    out->kind = kind;
    out->at_us = hal_clock_now_us();
}

/* Bytes the connection did not take wait here, as in a port's held input. */
static void keep(h_client_t *c, const uint8_t *bytes, size_t len)
{
    ck_assert_uint_le(c->held_len + len, sizeof(c->held));
    memcpy(c->held + c->held_len, bytes, len);
    c->held_len += len;
}

static void resume(void *ctx)
{
    h_client_t *c = ctx;
    size_t len = c->held_len;
    size_t taken = wsg_conn_input(&c->conn, c->held, len);
    memmove(c->held, c->held + taken, len - taken);
    c->held_len = len - taken;
}

static const wsg_conn_io_t capture_io = {.write = write_line, .resume = resume};

void h_open_on(h_client_t *c, wsg_device_t *device, const wsg_proto_driver_t *drv,
               wsg_transport_t transport)
{
    memset(c, 0, sizeof(*c));
    wsg_conn_open(&c->conn, device, drv, transport, &capture_io, c);
}

void h_close(h_client_t *c, wsg_close_reason_t reason)
{
    wsg_conn_close(&c->conn, reason);
}

void h_send_bytes(h_client_t *c, const void *bytes, size_t len)
{
    size_t taken = c->held_len == 0 ? wsg_conn_input(&c->conn, bytes, len) : 0;
    if (taken < len) {
        keep(c, (const uint8_t *)bytes + taken, len - taken);
    }
}

void send_line(h_client_t *c, const char *line)
{
    char buf[1024];
    size_t len = strlen(line);
    ck_assert_uint_lt(len, sizeof(buf));
    memcpy(buf, line, len);
    buf[len] = '\n';
    h_send_bytes(c, buf, len + 1);
}

size_t h_unread(const h_client_t *c)
{
    return c->count - c->read;
}

const char *h_next_line(h_client_t *c)
{
    if (c->read == c->count) {
        return "<no line>";
    }
    return c->lines[c->read++].text;
}

const h_line_t *h_last_read(const h_client_t *c)
{
    return c->read > 0 ? &c->lines[c->read - 1] : NULL;
}

const char *ask(h_client_t *c, const char *line)
{
    size_t before = c->count;
    send_line(c, line);
    if (c->count == before) {
        return "<no reply>";
    }
    return h_next_line(c);
}

bool h_take_line(h_client_t *c, const char *text)
{
    while (c->read < c->count) {
        if (strcmp(c->lines[c->read++].text, text) == 0) {
            return true;
        }
    }
    return false;
}

size_t h_count_prefix(h_client_t *c, const char *prefix)
{
    size_t n = 0;
    for (size_t i = c->read; i < c->count; i++) {
        if (strncmp(c->lines[i].text, prefix, strlen(prefix)) == 0) {
            n++;
        }
    }
    return n;
}

void h_discard(h_client_t *c)
{
    c->read = c->count;
}

void h_clear(h_client_t *c)
{
    c->count = 0;
    c->read = 0;
}

uint32_t h_gcl_lines_in(const h_client_t *c)
{
    wsg_gcl_conn_info_t info;
    ck_assert(wsg_gcl_conn_info(&c->conn, &info));
    return info.lines_in;
}

uint32_t h_gcl_lines_out(const h_client_t *c)
{
    wsg_gcl_conn_info_t info;
    ck_assert(wsg_gcl_conn_info(&c->conn, &info));
    return info.lines_out;
}
