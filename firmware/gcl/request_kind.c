/* SPDX-License-Identifier: BSD-3-Clause */
/* The kind of a GCL line for the command processor's service time
 * (docs/timing.md): read from the command's name without a parse, which
 * runs only when the line is served. */
#include <string.h>

#include "gcl/gcl_internal.h"

static bool is_name_char(char ch)
{
    return (ch >= 'A' && ch <= 'Z') || (ch >= 'a' && ch <= 'z') || ch == '_' ||
           (ch >= '0' && ch <= '9');
}

/* The commands that start or end a motion (manual: "Motion Control"). */
static bool is_motion(const char *name, size_t len)
{
    static const char *const motions[] = {"HOME", "MOVE",     "GRIP", "RELEASE",
                                          "STOP", "FASTSTOP", "FSACK"};
    for (size_t i = 0; i < sizeof(motions) / sizeof(motions[0]); i++) {
        if (strlen(motions[i]) == len && strncmp(motions[i], name, len) == 0) {
            return true;
        }
    }
    return false;
}

wsg_request_kind_t wsg_gcl_request_kind(const char *text, size_t len)
{
    size_t i = 0;
    while (i < len && text[i] == ' ') {
        i++;
    }
    size_t start = i;
    while (i < len && is_name_char(text[i])) {
        i++;
    }
    size_t name_len = i - start;
    while (i < len && (text[i] == ' ' || text[i] == '[')) {
        if (text[i] == '[') { /* an indexed query, NAME[i]? */
            while (i < len && text[i] != ']') {
                i++;
            }
        }
        i++;
    }
    if (i < len && text[i] == '?') {
        return WSG_REQ_QUERY;
    }
    return is_motion(text + start, name_len) ? WSG_REQ_MOTION : WSG_REQ_SETTING;
}
