/* SPDX-License-Identifier: BSD-3-Clause */
#include "wsg/gcl_parse.h"

#include <string.h>

typedef struct {
    const char *p;
    const char *end;
} cursor_t;

static bool is_space(char c)
{
    return c == ' ' || c == '\t';
}

/* Range checks as one unsigned comparison each: these run for every byte. */
static bool is_alpha(char c)
{
    return (unsigned)(((unsigned char)c | 0x20u) - 'a') < 26u || c == '_';
}

static bool is_digit(char c)
{
    return (unsigned)((unsigned char)c - '0') < 10u;
}

static char to_upper(char c)
{
    return (unsigned)((unsigned char)c - 'a') < 26u ? (char)(c - 'a' + 'A') : c;
}

static bool at_end(const cursor_t *cur)
{
    return cur->p >= cur->end;
}

static char peek(const cursor_t *cur)
{
    return at_end(cur) ? '\0' : *cur->p;
}

static void skip_space(cursor_t *cur)
{
    while (!at_end(cur) && is_space(*cur->p)) {
        cur->p++;
    }
}

static bool accept(cursor_t *cur, char c)
{
    skip_space(cur);
    if (peek(cur) != c) {
        return false;
    }
    cur->p++;
    return true;
}

/* Reads [A-Za-z_][A-Za-z0-9_]*; false if none. A name longer than max is
 * kept truncated (it still names an unknown command); a longer argument word
 * is refused. */
static bool read_word(cursor_t *cur, char *out, size_t max, bool is_name)
{
    skip_space(cur);
    if (!is_alpha(peek(cur))) {
        return false;
    }
    size_t n = 0;
    const char *p = cur->p;
    for (; p < cur->end; p++) {
        char c = *p;
        bool letter = (unsigned)(((unsigned char)c | 0x20u) - 'a') < 26u;
        if (!letter && !is_digit(c) && c != '_') {
            break;
        }
        if (n < max) {
            out[n++] = is_name && letter ? (char)((unsigned char)c & ~0x20u) : c; /* upper case */
        } else if (!is_name) {
            return false;
        }
    }
    cur->p = p;
    out[n] = '\0';
    return true;
}

static unsigned read_digits(cursor_t *cur, double *value)
{
    unsigned count = 0;
    while (!at_end(cur) && is_digit(*cur->p)) {
        *value = *value * 10.0 + (double)(*cur->p - '0');
        cur->p++;
        count++;
    }
    return count;
}

static double power_of_ten(int exponent)
{
    double result = 1.0;
    double base = exponent < 0 ? 0.1 : 10.0;
    int n = exponent < 0 ? -exponent : exponent;
    while (n-- > 0) {
        result *= base;
    }
    return result;
}

static bool read_exponent(cursor_t *cur, int *exponent)
{
    char sign = peek(cur);
    if (sign == '+' || sign == '-') {
        cur->p++;
    }
    double digits = 0.0;
    if (read_digits(cur, &digits) == 0 || digits > 300.0) {
        return false;
    }
    *exponent = sign == '-' ? -(int)digits : (int)digits;
    return true;
}

/* [+-]digits[.digits][(e|E)[+-]digits], or [+-].digits[...]. */
static bool read_number(cursor_t *cur, gcl_arg_t *arg)
{
    bool negative = false;
    if (peek(cur) == '+' || peek(cur) == '-') {
        negative = *cur->p == '-';
        cur->p++;
    }
    double value = 0.0;
    unsigned digits = read_digits(cur, &value);
    arg->integer_syntax = true;
    if (peek(cur) == '.') {
        cur->p++;
        arg->integer_syntax = false;
        double fraction = 0.0;
        unsigned places = read_digits(cur, &fraction);
        value += fraction * power_of_ten(-(int)places);
        digits += places;
    }
    if (digits == 0) {
        return false;
    }
    if (peek(cur) == 'e' || peek(cur) == 'E') {
        cur->p++;
        int exponent = 0;
        if (!read_exponent(cur, &exponent)) {
            return false;
        }
        arg->integer_syntax = false;
        value *= power_of_ten(exponent);
    }
    arg->kind = GCL_ARG_NUMBER;
    arg->number = negative ? -value : value;
    return true;
}

static bool read_string(cursor_t *cur, gcl_arg_t *arg)
{
    cur->p++; /* opening quote */
    size_t n = 0;
    while (!at_end(cur) && *cur->p != '"') {
        if (n == GCL_STRING_MAX) {
            return false;
        }
        arg->text[n++] = *cur->p++;
    }
    if (at_end(cur)) {
        return false; /* unterminated */
    }
    cur->p++;
    arg->text[n] = '\0';
    arg->kind = GCL_ARG_STRING;
    return true;
}

static bool read_arg(cursor_t *cur, gcl_arg_t *arg)
{
    memset(arg, 0, sizeof(*arg));
    skip_space(cur);
    char c = peek(cur);
    if (c == '"') {
        return read_string(cur, arg);
    }
    if (is_alpha(c)) {
        arg->kind = GCL_ARG_WORD;
        return read_word(cur, arg->text, GCL_STRING_MAX, false);
    }
    bool ok = read_number(cur, arg);
    /* "12abc" is not a number followed by garbage but one bad token */
    return ok && !is_alpha(peek(cur)) && !is_digit(peek(cur));
}

static wsg_status_t read_call_args(cursor_t *cur, gcl_command_t *cmd)
{
    if (accept(cur, ')')) {
        return E_SUCCESS;
    }
    do {
        gcl_arg_t scratch;
        gcl_arg_t *arg = cmd->argc < GCL_ARGS_MAX ? &cmd->args[cmd->argc] : &scratch;
        skip_space(cur);
        char c = peek(cur);
        if (c == ',' || c == ')' || c == '\0') {
            return E_CMD_FORMAT_ERROR; /* empty argument */
        }
        if (!read_arg(cur, arg)) {
            return E_INVALID_PARAMETER;
        }
        cmd->argc++;
    } while (accept(cur, ','));
    return accept(cur, ')') ? E_SUCCESS : E_CMD_FORMAT_ERROR;
}

static wsg_status_t read_index(cursor_t *cur, gcl_command_t *cmd)
{
    gcl_arg_t arg;
    skip_space(cur);
    if (!read_number(cur, &arg) || !arg.integer_syntax || arg.number > 2147483647.0 ||
        arg.number < -2147483647.0) {
        return E_CMD_FORMAT_ERROR;
    }
    cmd->index = (int32_t)arg.number;
    if (!accept(cur, ']') || !accept(cur, '?')) {
        return E_CMD_FORMAT_ERROR;
    }
    return E_SUCCESS;
}

static wsg_status_t read_form(cursor_t *cur, gcl_command_t *cmd)
{
    skip_space(cur);
    char c = peek(cur);
    if (at_end(cur)) {
        return E_CMD_FORMAT_ERROR;
    }
    cur->p++;
    switch (c) {
    case '(':
        cmd->form = GCL_FORM_CALL;
        return read_call_args(cur, cmd);
    case '?':
        cmd->form = GCL_FORM_QUERY;
        return E_SUCCESS;
    case '[':
        cmd->form = GCL_FORM_INDEXED_QUERY;
        return read_index(cur, cmd);
    case '=':
        cmd->form = GCL_FORM_SET;
        skip_space(cur);
        if (at_end(cur)) {
            return E_CMD_FORMAT_ERROR;
        }
        cmd->argc = 1;
        return read_arg(cur, &cmd->args[0]) ? E_SUCCESS : E_INVALID_PARAMETER;
    default:
        return E_CMD_FORMAT_ERROR;
    }
}

wsg_status_t wsg_gcl_parse_line(const char *line, size_t len, gcl_command_t *cmd)
{
    memset(cmd, 0, sizeof(*cmd));
    cursor_t cur = {line, line + len};
    if (!read_word(&cur, cmd->name, GCL_NAME_MAX, true)) {
        cmd->name[0] = '\0';
        return E_CMD_FORMAT_ERROR;
    }
    wsg_status_t status = read_form(&cur, cmd);
    if (status != E_SUCCESS) {
        return status;
    }
    skip_space(&cur);
    return at_end(&cur) ? E_SUCCESS : E_CMD_FORMAT_ERROR;
}

bool wsg_gcl_text_equals(const char *text, const char *upper)
{
    while (*text != '\0' && *upper != '\0') {
        if (to_upper(*text) != *upper) {
            return false;
        }
        text++;
        upper++;
    }
    return *text == '\0' && *upper == '\0';
}

/* The length of text's first run of bytes from set (strspn(), which the
 * microcontroller port's C library subset lacks). */
static size_t span_of(const char *text, const char *set)
{
    size_t n = 0;
    while (text[n] != '\0' && strchr(set, text[n]) != NULL) {
        n++;
    }
    return n;
}

/* "Host: ...": an HTTP header's name (a token) and its colon. */
static bool header_line(const char *line)
{
    size_t name = span_of(line, "!#$%&'*+-.^_`|~0123456789"
                                "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz");
    return name > 0 && line[name] == ':';
}

/* "POST /path HTTP/1.1": a method in capitals, a space and a request target
 * (a path, "*", or an absolute URL). Checked on the line's first bytes: a
 * long URL makes the line too long for a command, not less of a request. */
static bool request_line(const char *line)
{
    size_t method = span_of(line, "ABCDEFGHIJKLMNOPQRSTUVWXYZ");
    const char *target = line + method + 1;
    return method > 0 && line[method] == ' ' &&
           (target[0] == '/' || target[0] == '*' || strncmp(target, "http://", 7) == 0 ||
            strncmp(target, "https://", 8) == 0);
}

bool wsg_gcl_line_is_http(const char *line)
{
    return request_line(line) || header_line(line);
}
