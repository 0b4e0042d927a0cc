/* SPDX-License-Identifier: BSD-3-Clause */
/* GCL lexical and syntactic layer: one complete line in, one command out. */
#ifndef GCL_PARSE_H
#define GCL_PARSE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "wsg_opts.h"
#include "wsg_status.h"

#define GCL_LINE_MAX WSG_GCL_LINE_MAX /* longest accepted line, without its terminator */
#define GCL_NAME_MAX 15
#define GCL_ARGS_MAX 4    /* arguments stored; more are counted, not kept */
#define GCL_STRING_MAX 31 /* longest string or word argument */

typedef enum {
    GCL_FORM_CALL = 1u << 0,          /* NAME(args) */
    GCL_FORM_QUERY = 1u << 1,         /* NAME? */
    GCL_FORM_INDEXED_QUERY = 1u << 2, /* NAME[i]? */
    GCL_FORM_SET = 1u << 3,           /* NAME=value */
} gcl_form_t;

typedef enum {
    GCL_ARG_NUMBER, /* 50, -3, 50.00, 1e2 */
    GCL_ARG_STRING, /* "POS" */
    GCL_ARG_WORD,   /* POS, true: an unquoted identifier */
} gcl_arg_kind_t;

typedef struct {
    gcl_arg_kind_t kind;
    bool integer_syntax; /* a number written without '.' or exponent */
    double number;
    char text[GCL_STRING_MAX + 1]; /* string contents or word, as sent */
} gcl_arg_t;

typedef struct {
    char name[GCL_NAME_MAX + 1]; /* upper case; empty if the line has no name */
    gcl_form_t form;
    int32_t index; /* GCL_FORM_INDEXED_QUERY only */
    unsigned argc; /* arguments given (may exceed GCL_ARGS_MAX) */
    gcl_arg_t args[GCL_ARGS_MAX];
} gcl_command_t;

/* Parses line[0..len) (no terminator). On failure returns E_CMD_FORMAT_ERROR,
 * or E_INVALID_PARAMETER for an argument that is not a valid token, and still
 * fills cmd->name when the line starts with a name. */
wsg_status_t wsg_gcl_parse_line(const char *line, size_t len, gcl_command_t *cmd);

/* Case-insensitive comparison of a word or string argument. */
bool wsg_gcl_text_equals(const char *text, const char *upper);

/* The line (NUL-terminated) is one only an HTTP client sends: a request
 * line ("POST /path HTTP/1.1": a method in capitals, a space, then '/', '*'
 * or an absolute URL) or a header ("Host: ..."). No command looks like one
 * (a name is followed by '(', '?', '=' or '['). A web page can make a
 * browser send a cross-site POST to any port, the lines of its body
 * commands: a connection that sends such a line is closed before any of it
 * runs, as Redis does (docs/behaviour.md). */
bool wsg_gcl_line_is_http(const char *line);

#endif
