/* SPDX-License-Identifier: BSD-3-Clause */
#include "wsg/gcl_linebuf.h"

static void start_line(gcl_linebuf_t *lb)
{
    lb->len = 0;
    lb->too_long = false;
    lb->bad_byte = false;
    lb->complete = false;
    lb->text[0] = '\0';
}

void gcl_linebuf_reset(gcl_linebuf_t *lb)
{
    start_line(lb);
    lb->ended_by_cr = false;
}

static bool is_bad_byte(uint8_t byte)
{
    return (byte < 0x20u && byte != '\t') || byte >= 0x7fu;
}

static void finish_line(gcl_linebuf_t *lb)
{
    lb->text[lb->len] = '\0';
    lb->complete = true;
}

bool gcl_linebuf_feed(gcl_linebuf_t *lb, uint8_t byte)
{
    bool after_cr = lb->ended_by_cr;
    lb->ended_by_cr = false;
    if (byte == '\n' && after_cr) {
        return false; /* the second half of a "\r\n": that line has ended already */
    }
    if (lb->complete) {
        start_line(lb); /* the previous line has been handed out */
    }
    if (byte == '\n' || byte == '\r') {
        finish_line(lb);
        lb->ended_by_cr = byte == '\r';
        return true;
    }
    if (is_bad_byte(byte)) {
        lb->bad_byte = true;
        return false;
    }
    if (lb->len >= GCL_LINE_MAX) {
        lb->too_long = true;
        return false;
    }
    lb->text[lb->len++] = (char)byte;
    return false;
}

bool gcl_linebuf_flush(gcl_linebuf_t *lb)
{
    if (!gcl_linebuf_pending(lb)) {
        return false;
    }
    finish_line(lb);
    return true;
}

gcl_line_status_t gcl_linebuf_status(const gcl_linebuf_t *lb)
{
    if (lb->bad_byte) {
        return GCL_LINE_BAD_BYTE;
    }
    return lb->too_long ? GCL_LINE_TOO_LONG : GCL_LINE_OK;
}

bool gcl_linebuf_pending(const gcl_linebuf_t *lb)
{
    return !lb->complete && (lb->len > 0 || lb->too_long || lb->bad_byte);
}
