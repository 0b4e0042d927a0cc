/* SPDX-License-Identifier: BSD-3-Clause */
#include "wsg/gcl_linebuf.h"

#include "priv/small_bytes.h"

static void start_line(gcl_linebuf_t *lb)
{
    lb->len = 0;
    lb->too_long = false;
    lb->bad_byte = false;
    lb->complete = false;
    lb->text[0] = '\0';
}

void wsg_gcl_linebuf_reset(gcl_linebuf_t *lb)
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

bool wsg_gcl_linebuf_feed(gcl_linebuf_t *lb, uint8_t byte)
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

/* A byte that wsg_gcl_linebuf_feed() appends to an open line without more ado. */
static bool is_plain_byte(uint8_t byte)
{
    return (unsigned)(byte - 0x20u) < 0x5fu || byte == '\t';
}

/* The common case in one tight loop (a pipelined client sends many lines per
 * write): plain bytes and a line end that is not the "\n" of a "\r\n". Every
 * other byte goes through wsg_gcl_linebuf_feed(), which says what they mean. */
size_t wsg_gcl_linebuf_feed_bytes(gcl_linebuf_t *lb, const uint8_t *bytes, size_t len,
                                  bool *line_done)
{
    size_t i = 0;
    *line_done = false;
    while (i < len) {
        if (!lb->ended_by_cr) {
            if (lb->complete) {
                start_line(lb); /* the previous line has been handed out */
            }
            size_t room = GCL_LINE_MAX - lb->len;
            size_t end = len - i < room ? len : i + room;
            char *text = lb->text + lb->len;
            size_t start = i;
            while (i < end && is_plain_byte(bytes[i])) {
                *text++ = (char)bytes[i++];
            }
            lb->len += i - start;
            if (i == len) {
                break;
            }
            uint8_t byte = bytes[i];
            if (byte == '\n' || byte == '\r') {
                i++;
                finish_line(lb);
                lb->ended_by_cr = byte == '\r';
                *line_done = true;
                break;
            }
        }
        if (wsg_gcl_linebuf_feed(lb, bytes[i++])) {
            *line_done = true;
            break;
        }
    }
    return i;
}

/* Between two lines: the next byte that is not the "\n" of a "\r\n" starts one. */
static bool between_lines(const gcl_linebuf_t *lb)
{
    return lb->complete || (lb->len == 0 && !lb->too_long && !lb->bad_byte);
}

size_t wsg_gcl_linebuf_take_line(gcl_linebuf_t *lb, const uint8_t *bytes, size_t len,
                                 const char *line, size_t line_len)
{
    if (line_len == 0 || line_len >= len || !between_lines(lb)) {
        return 0;
    }
    uint8_t end = bytes[line_len];
    if (end != '\n' && end != '\r') {
        return 0;
    }
    if (!wsg_small_equal(bytes, line, line_len)) {
        return 0;
    }
    wsg_small_copy(lb->text, line, line_len);
    lb->len = line_len;
    lb->too_long = false;
    lb->bad_byte = false;
    finish_line(lb);
    lb->ended_by_cr = end == '\r';
    return line_len + 1u;
}

bool wsg_gcl_linebuf_flush(gcl_linebuf_t *lb)
{
    if (!wsg_gcl_linebuf_pending(lb)) {
        return false;
    }
    finish_line(lb);
    return true;
}

bool wsg_gcl_linebuf_pending(const gcl_linebuf_t *lb)
{
    return !lb->complete && (lb->len > 0 || lb->too_long || lb->bad_byte);
}
