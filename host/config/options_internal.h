/* SPDX-License-Identifier: BSD-3-Clause */
/* What options.c and options_help.c share: the defaults, which --help
 * names, and the printing of --help and --list-models. */
#ifndef HOST_OPTIONS_INTERNAL_H
#define HOST_OPTIONS_INTERNAL_H

#include <stdbool.h>

#include "options.h"

#define DEFAULT_PORT 1000
#define DEFAULT_MAX_CLIENTS 8
#define MAX_CLIENTS_LIMIT 128
#define DEFAULT_PART_STIFFNESS 100.0f
#define DEFAULT_UDP_PEER_TIMEOUT_S 60
#define DEFAULT_BINARY_UDP_PORT 1500
#define DEFAULT_BINARY_UDP_REPLY_PORT 1501
#define DEFAULT_HTTP_PORT 8080
#define DEFAULT_HTTP_REQUEST_TIMEOUT_S 10
/* --seed: a fixed default, so that every run is the same (docs/timing.md) */
#define DEFAULT_SEED 1u
#define TIMEOUT_LIMIT_S 86400

/* --help, on stdout. */
void options_print_help(void);
/* --list-models [--json], on stdout. */
void options_list_models(bool json);

#endif
