/* SPDX-License-Identifier: BSD-3-Clause */
/* Command-line options of build/wsgsim: options_parse() reads the
 * configuration files (config_file.h), then the command line over them,
 * into host_options_t (host_options.h). */
#ifndef HOST_OPTIONS_H
#define HOST_OPTIONS_H

#include "host_options.h"

typedef enum { OPTIONS_RUN, OPTIONS_EXIT_OK, OPTIONS_EXIT_USAGE } options_result_t;

/* Parses argv; prints help, version, model list or a usage error itself.
 * Whatever it returns, opts->config is to be released (options_release). */
options_result_t options_parse(int argc, char **argv, host_options_t *opts);
/* Frees what options_parse() made (the configuration read); opts->config
 * is NULL after. */
void options_release(host_options_t *opts);

#endif
