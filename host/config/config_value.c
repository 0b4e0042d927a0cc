/* SPDX-License-Identifier: BSD-3-Clause */
#include "config_value.h"

#include <arpa/inet.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "http_host.h"
#include "net_allow.h"
#include "wire_spec.h"
#include "host_options.h"
#include "sim/finger_node.h"
#include "sim/sim_models.h"
#include "wsg/wsg_config.h"

#define TEXT_MAX WSG_CONFIG_STRING_MAX
#define MAX_CLIENTS_LIMIT 128

static bool parse_number(const char *text, double *out)
{
    char *end = NULL;
    errno = 0;
    double v = strtod(text, &end);
    if (end == text || *end != '\0' || errno != 0 || !isfinite(v)) {
        return false;
    }
    *out = v;
    return true;
}

static bool parse_bool(const char *text, double *out)
{
    static const char *const yes[] = {"yes", "true", "on", "1"};
    static const char *const no[] = {"no", "false", "off", "0"};
    for (unsigned i = 0; i < 4; i++) {
        if (strcasecmp(text, yes[i]) == 0 || strcasecmp(text, no[i]) == 0) {
            *out = strcasecmp(text, yes[i]) == 0 ? 1.0 : 0.0;
            return true;
        }
    }
    return false;
}

bool config_value_int_range(const char *text, double min, double max, double *out)
{
    return parse_number(text, out) && *out == floor(*out) && *out >= min && *out <= max;
}

static bool is_loopback(const char *addr)
{
    struct in_addr v4;
    struct in6_addr v6;
    if (inet_pton(AF_INET, addr, &v4) == 1) {
        return (ntohl(v4.s_addr) >> 24) == 127u;
    }
    return inet_pton(AF_INET6, addr, &v6) == 1 && IN6_IS_ADDR_LOOPBACK(&v6);
}

static bool is_address(const char *addr)
{
    unsigned char buf[sizeof(struct in6_addr)];
    return inet_pton(AF_INET, addr, buf) == 1 || inet_pton(AF_INET6, addr, buf) == 1;
}

static bool text_ok_long(const char *text)
{
    for (const char *p = text; *p != '\0'; p++) {
        if (*p < 0x20 || *p > 0x7e) {
            return false;
        }
    }
    return true;
}

/* The device's own rule for its texts (wsg_config_text_char_ok). */
static bool text_ok(const char *text)
{
    for (const char *p = text; *p != '\0'; p++) {
        if (!wsg_config_text_char_ok(*p)) {
            return false;
        }
    }
    return strlen(text) < TEXT_MAX;
}

/* The kinds that are numbers (their value in v->number). */
static const char *convert_number(config_value_kind_t kind, const char *text, config_value_t *v)
{
    switch (kind) {
    case CV_SERIAL:
        return config_value_int_range(text, 0, 4294967295.0, &v->number)
                   ? NULL
                   : "expected an integer 0-4294967295";
    case CV_BYTE:
        return config_value_int_range(text, 0, 255, &v->number) ? NULL
                                                                : "expected an integer 0-255";
    case CV_NUMBER:
        return parse_number(text, &v->number) ? NULL : "expected a number";
    case CV_BOOL:
        return parse_bool(text, &v->number) ? NULL : "expected yes/no, true/false, on/off or 1/0";
    case CV_DIRECTION:
        v->number = strcasecmp(text, "positive") == 0 ? 1.0 : 0.0;
        return strcasecmp(text, "positive") == 0 || strcasecmp(text, "negative") == 0
                   ? NULL
                   : "expected positive or negative";
    case CV_PORT:
        return config_value_int_range(text, 0, 65535, &v->number) ? NULL
                                                                  : "expected a port 0-65535";
    case CV_PORT_OFF:
        v->number = -1.0;
        return strcasecmp(text, "off") == 0 || config_value_int_range(text, 0, 65535, &v->number)
                   ? NULL
                   : "expected a port 0-65535 or off";
    case CV_CLIENTS:
        return config_value_int_range(text, 1, MAX_CLIENTS_LIMIT, &v->number) ? NULL
                                                                              : "expected 1-128";
    case CV_SECONDS:
        return config_value_int_range(text, 1, 86400, &v->number) ? NULL
                                                                  : "expected seconds 1-86400";
    case CV_SECONDS_OFF:
        v->number = 0.0;
        return strcasecmp(text, "off") == 0 || config_value_int_range(text, 0, 86400, &v->number)
                   ? NULL
                   : "expected seconds 0-86400 or off";
    case CV_MILLISECONDS:
        return config_value_int_range(text, 1, HOST_MILLISECONDS_MAX, &v->number)
                   ? NULL
                   : "expected milliseconds 1-3600000";
    case CV_PROTOCOL: {
        host_protocol_t protocol = HOST_PROTOCOL_AUTO;
        bool ok = options_parse_protocol(text, &protocol);
        v->number = (double)protocol;
        return ok ? NULL : "expected auto, gcl or binary";
    }
    case CV_PHYSICS: {
        host_physics_t physics = HOST_PHYSICS_BUILTIN;
        bool ok = options_parse_physics(text, &physics);
        v->number = (double)physics;
        return ok ? NULL : "expected builtin, mujoco or socket:PATH";
    }
    default:
        return "unsupported";
    }
}

/* The kinds that are texts (kept in v->text as written). */
static const char *convert_text(config_value_kind_t kind, const char *text, config_value_t *v)
{
    switch (kind) {
    case CV_TEXT:
        return text_ok(text) ? NULL : "expected printable text without '\"', at most 47 characters";
    case CV_MODEL:
        return wsg_sim_model_find(text) != NULL ? NULL : "unknown model (see wsgsim --list-models)";
    case CV_ADDR:
        return is_address(text) ? NULL : "expected an IPv4 or IPv6 address";
    case CV_HOSTS:
        return strlen(text) < sizeof(v->text) && http_host_list_valid(text)
                   ? NULL
                   : "expected host names separated by commas (or *), at most 127 characters";
    case CV_PATH:
        return text[0] != '\0' && strlen(text) < sizeof(v->text) - 1u && text_ok_long(text)
                   ? NULL
                   : "expected a path of printable characters";
    case CV_FINGERS: {
        fbus_type_t types[FBUS_SLOTS];
        return wsg_finger_node_parse_pair(text, types)
                   ? NULL
                   : "expected fingers A[,B], each none, generic, fmf or dsa";
    }
    case CV_ALLOW: {
        net_allow_t list = {.count = 0};
        return strlen(text) < sizeof(v->text) && net_allow_add(&list, text)
                   ? NULL
                   : "expected up to 8 comma-separated addresses, each ADDR or ADDR/PREFIX";
    }
    case CV_NET: {
        wire_spec_t spec = {0};
        if (strlen(text) >= sizeof(v->text)) {
            return "expected wire conditions of at most 127 characters";
        }
        return wire_spec_parse(&spec, text, v->why, sizeof(v->why)) ? NULL : v->why;
    }
    case CV_LOOPBACK:
        return is_loopback(text) ? NULL
                                 : "the control port may only be bound to a loopback address "
                                   "here; use --sim-bind on the command line to expose it";
    default:
        return convert_number(kind, text, v);
    }
}

/* Converts one value by its kind; NULL when fine, else why not. */
const char *config_value_convert(config_value_kind_t kind, const char *text, config_value_t *v)
{
    snprintf(v->text, sizeof(v->text), "%s", text);
    return convert_text(kind, text, v);
}
