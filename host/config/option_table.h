/* SPDX-License-Identifier: BSD-3-Clause */
/* The options a run takes both from the command line and from the
 * configuration file, one row each: the option's name, the file's key, the
 * kind of value the key takes and where the value goes in host_options_t.
 * The configuration file reads its keys through this table and the
 * command line applies what it parsed through it: one way into the
 * options for both. */
#ifndef HOST_OPTION_TABLE_H
#define HOST_OPTION_TABLE_H

#include "config_value.h"
#include "host_options.h"

typedef enum {
    OPTION_MODEL,
    OPTION_TCP_PORT,
    OPTION_UDP_PORT,
    OPTION_BIND,
    OPTION_MAX_CLIENTS,
    OPTION_ADDRESS_PER_DEVICE,
    OPTION_IDLE_TIMEOUT,
    OPTION_UDP_PEER_TIMEOUT,
    OPTION_UDP_STREAM_ALLOW,
    OPTION_SIM_PORT,
    OPTION_SIM_BIND,
    OPTION_PROTOCOL,
    OPTION_BINARY_UDP_PORT,
    OPTION_BINARY_UDP_REPLY_PORT,
    OPTION_HTTP_PORT,
    OPTION_HTTP_BIND,
    OPTION_HTTP_ALLOW_HOST,
    OPTION_HTTP_REQUEST_TIMEOUT,
    OPTION_SCRIPT,
    OPTION_SCRIPT_DIR,
    OPTION_SCRIPT_AUTOSTART,
    OPTION_TIMING,
    OPTION_SEED,
    OPTION_PHYSICS,
    OPTION_SCENE,
    OPTION_PLANT_TIMEOUT,
    OPTION_NET,
    OPTION_COUNT
} option_id_t;

typedef struct {
    const char *cli;          /* the command line's name, "--tcp-port" */
    const char *section;      /* the file's section and key, */
    const char *key;          /* "[network] tcp_port" */
    config_value_kind_t kind; /* what the file's key takes */
    /* Writes a value into opts: its number, or its text, which must
     * outlive opts (the file read, or argv); false when opts cannot take
     * it (a list that is full). */
    bool (*set)(host_options_t *opts, double number, const char *text);
} option_row_t;

extern const option_row_t option_table[OPTION_COUNT];

/* Writes row id's value into opts (option_row_t.set). */
static inline bool option_set(host_options_t *opts, option_id_t id, double number, const char *text)
{
    return option_table[id].set(opts, number, text);
}

#endif
