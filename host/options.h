/* Command-line options of build/wsgsim. */
#ifndef HOST_OPTIONS_H
#define HOST_OPTIONS_H

#include <stdbool.h>

typedef struct {
    int tcp_port;
    int udp_port;
    bool tcp_enabled;
    bool udp_enabled;
    const char *bind_addr;
    const char *model;
    bool part_given;
    float part_width_mm;
    float part_stiffness_n_mm;
    int max_clients;
    bool disconnect_faststop;
    bool trace;
} host_options_t;

typedef enum { OPTIONS_RUN, OPTIONS_EXIT_OK, OPTIONS_EXIT_USAGE } options_result_t;

/* Parses argv; prints help, version, model list or a usage error itself. */
options_result_t options_parse(int argc, char **argv, host_options_t *opts);

#endif
