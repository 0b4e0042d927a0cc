/* SPDX-License-Identifier: BSD-3-Clause */
/* The kinds of value a setting of the configuration takes, and how each
 * is read from its text: a port, seconds, an address, a model, ... (the
 * configuration file's keys; docs/wsgsim.example.ini). */
#ifndef HOST_CONFIG_VALUE_H
#define HOST_CONFIG_VALUE_H

#include <stdbool.h>

/* A value's text as written, with its NUL. */
#define CONFIG_VALUE_TEXT_MAX 128
#define CONFIG_VALUE_WHY_MAX 160

typedef enum {
    CV_TEXT,         /* printable, no '"', shorter than WSG_CONFIG_STRING_MAX */
    CV_MODEL,        /* a model wsg_sim_model_find() knows */
    CV_SERIAL,       /* 0..4294967295 */
    CV_BYTE,         /* 0..255 */
    CV_NUMBER,       /* a finite number; ranges are checked against the model */
    CV_BOOL,         /* yes/no, true/false, on/off, 1/0 */
    CV_DIRECTION,    /* positive/negative */
    CV_PORT,         /* 0..65535 */
    CV_PORT_OFF,     /* 0..65535 or "off" (-1) */
    CV_CLIENTS,      /* 1..128 */
    CV_SECONDS,      /* 1..86400 */
    CV_SECONDS_OFF,  /* 0..86400 or "off" (0) */
    CV_MILLISECONDS, /* 1..3600000 (an hour) */
    CV_ADDR,         /* an IPv4 or IPv6 address */
    CV_LOOPBACK,     /* a loopback address only */
    CV_PROTOCOL,     /* auto, gcl or binary */
    CV_PHYSICS,      /* builtin, mujoco or socket:PATH */
    CV_HOSTS,        /* host names, comma-separated (http_host_list_valid) */
    CV_PATH,         /* a file or directory name: printable, not empty */
    CV_ALLOW,        /* comma-separated ADDR[/PREFIX] (net_allow.h) */
    CV_FINGERS,      /* A[,B]: the fingers of a loopback bus (wsg_finger_node_parse_pair) */
    CV_NET,          /* wire conditions: a preset and KEY=VALUE items (wire_spec.h) */
} config_value_kind_t;

typedef struct {
    double number;                    /* a number's, a switch's (0/1), a choice's */
    char text[CONFIG_VALUE_TEXT_MAX]; /* as written */
    char why[CONFIG_VALUE_WHY_MAX];   /* a reason worked out for this text */
} config_value_t;

/* Reads text as a value of kind into v (its text kept as written); NULL
 * when it is one, else why not (a fixed text, or v->why). */
const char *config_value_convert(config_value_kind_t kind, const char *text, config_value_t *v);
/* An integer within [min, max] (written as one: "3", not "3.0e0"). */
bool config_value_int_range(const char *text, double min, double max, double *out);

#endif
