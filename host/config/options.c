/* SPDX-License-Identifier: BSD-3-Clause */
#include "options.h"

#include <getopt.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "config_file.h"
#include "option_table.h"
#include "options_internal.h"
#include "log.h"
#include "script_options.h"
#include "timing_profile.h"
#include "sim/finger_node.h"
#include "sim/sim_models.h"
#include "version.h"
#include "http_host.h"

static bool parse_int(const char *text, int min, int max, int *out)
{
    char *end = NULL;
    long value = strtol(text, &end, 10);
    if (end == text || *end != '\0' || value < min || value > max) {
        return false;
    }
    *out = (int)value;
    return true;
}

static bool parse_positive_float(const char *text, char **end, float *out)
{
    float value = strtof(text, end);
    if (*end == text || !(value > 0.0f)) {
        return false;
    }
    *out = value;
    return true;
}

/* W or W:K */
static bool parse_part(const char *text, host_options_t *opts)
{
    char *end = NULL;
    if (!parse_positive_float(text, &end, &opts->part_width_mm)) {
        return false;
    }
    if (*end == ':') {
        const char *k = end + 1;
        if (!parse_positive_float(k, &end, &opts->part_stiffness_n_mm)) {
            return false;
        }
    }
    opts->part_given = true;
    return *end == '\0';
}

/* getopt's codes: the options of option_table.h are OPT_TABLE + their row,
 * the command line's own ones follow. */
enum {
    OPT_TABLE = 256,
    OPT_NO_TCP = OPT_TABLE + OPTION_COUNT,
    OPT_NO_UDP,
    OPT_LIST_MODELS,
    OPT_PART,
    OPT_DEVICES,
    OPT_NO_DISCONNECT_FASTSTOP,
    OPT_TRACE,
    OPT_CAN,
    OPT_FINGERS,
    OPT_CONFIG,
    OPT_SAVE_FILE,
    OPT_SCENARIO,
    OPT_START_PAUSED,
    OPT_RECORD,
    OPT_COVERAGE,
    OPT_STRICT,
    OPT_BINARY_NO_CRC,
    OPT_JSON,
    OPT_CAN_LOG,
    OPT_LOG_LEVEL,
    OPT_QUIET,
    OPT_LOG_TIMESTAMPS,
    OPT_LOG_FILE,
    OPT_READY_FILE,
    OPT_VERSION = 'V',
    OPT_HELP = 'h',
};
#define SHORT_OPTIONS ":hV" /* leading ':': a missing argument returns ':' */

static const struct option long_options[] = {
    {"tcp-port", required_argument, NULL, OPT_TABLE + OPTION_TCP_PORT},
    {"udp-port", required_argument, NULL, OPT_TABLE + OPTION_UDP_PORT},
    {"no-tcp", no_argument, NULL, OPT_NO_TCP},
    {"no-udp", no_argument, NULL, OPT_NO_UDP},
    {"bind", required_argument, NULL, OPT_TABLE + OPTION_BIND},
    {"model", required_argument, NULL, OPT_TABLE + OPTION_MODEL},
    {"list-models", no_argument, NULL, OPT_LIST_MODELS},
    {"part", required_argument, NULL, OPT_PART},
    {"max-clients", required_argument, NULL, OPT_TABLE + OPTION_MAX_CLIENTS},
    {"devices", required_argument, NULL, OPT_DEVICES},
    {"address-per-device", no_argument, NULL, OPT_TABLE + OPTION_ADDRESS_PER_DEVICE},
    {"no-disconnect-faststop", no_argument, NULL, OPT_NO_DISCONNECT_FASTSTOP},
    {"idle-timeout", required_argument, NULL, OPT_TABLE + OPTION_IDLE_TIMEOUT},
    {"udp-peer-timeout", required_argument, NULL, OPT_TABLE + OPTION_UDP_PEER_TIMEOUT},
    {"udp-stream-allow", required_argument, NULL, OPT_TABLE + OPTION_UDP_STREAM_ALLOW},
    {"trace", no_argument, NULL, OPT_TRACE},
    {"can", required_argument, NULL, OPT_CAN},
    {"fingers", required_argument, NULL, OPT_FINGERS},
    {"config", required_argument, NULL, OPT_CONFIG},
    {"save-file", required_argument, NULL, OPT_SAVE_FILE},
    {"sim-port", required_argument, NULL, OPT_TABLE + OPTION_SIM_PORT},
    {"sim-bind", required_argument, NULL, OPT_TABLE + OPTION_SIM_BIND},
    {"scenario", required_argument, NULL, OPT_SCENARIO},
    {"start-paused", no_argument, NULL, OPT_START_PAUSED},
    {"record", required_argument, NULL, OPT_RECORD},
    {"coverage", required_argument, NULL, OPT_COVERAGE},
    {"strict", no_argument, NULL, OPT_STRICT},
    {"protocol", required_argument, NULL, OPT_TABLE + OPTION_PROTOCOL},
    {"binary-udp-port", required_argument, NULL, OPT_TABLE + OPTION_BINARY_UDP_PORT},
    {"binary-udp-reply-port", required_argument, NULL, OPT_TABLE + OPTION_BINARY_UDP_REPLY_PORT},
    {"binary-no-crc", no_argument, NULL, OPT_BINARY_NO_CRC},
    {"http-port", required_argument, NULL, OPT_TABLE + OPTION_HTTP_PORT},
    {"http-bind", required_argument, NULL, OPT_TABLE + OPTION_HTTP_BIND},
    {"http-allow-host", required_argument, NULL, OPT_TABLE + OPTION_HTTP_ALLOW_HOST},
    {"http-request-timeout", required_argument, NULL, OPT_TABLE + OPTION_HTTP_REQUEST_TIMEOUT},
    {"json", no_argument, NULL, OPT_JSON},
    {"can-log", required_argument, NULL, OPT_CAN_LOG},
    {"log-level", required_argument, NULL, OPT_LOG_LEVEL},
    {"quiet", no_argument, NULL, OPT_QUIET},
    {"log-timestamps", no_argument, NULL, OPT_LOG_TIMESTAMPS},
    {"log-file", required_argument, NULL, OPT_LOG_FILE},
    {"ready-file", required_argument, NULL, OPT_READY_FILE},
    {"script", required_argument, NULL, OPT_TABLE + OPTION_SCRIPT},
    {"script-dir", required_argument, NULL, OPT_TABLE + OPTION_SCRIPT_DIR},
    {"timing", required_argument, NULL, OPT_TABLE + OPTION_TIMING},
    {"seed", required_argument, NULL, OPT_TABLE + OPTION_SEED},
    {"no-script-autostart", no_argument, NULL, OPT_TABLE + OPTION_SCRIPT_AUTOSTART},
    {"physics", required_argument, NULL, OPT_TABLE + OPTION_PHYSICS},
    {"scene", required_argument, NULL, OPT_TABLE + OPTION_SCENE},
    {"plant-timeout", required_argument, NULL, OPT_TABLE + OPTION_PLANT_TIMEOUT},
    {"net", required_argument, NULL, OPT_TABLE + OPTION_NET},
    {"version", no_argument, NULL, OPT_VERSION},
    {"help", no_argument, NULL, OPT_HELP},
    {NULL, 0, NULL, 0},
};

static void set_defaults(host_options_t *opts)
{
    memset(opts, 0, sizeof(*opts));
    opts->log_level = HAL_LOG_INFO;
    opts->tcp_port = DEFAULT_PORT;
    opts->udp_port = DEFAULT_PORT;
    opts->tcp_enabled = true;
    opts->udp_enabled = true;
    opts->bind_addr = "0.0.0.0";
    opts->model = wsg_sim_model_default()->name;
    opts->part_stiffness_n_mm = DEFAULT_PART_STIFFNESS;
    opts->max_clients = DEFAULT_MAX_CLIENTS;
    opts->devices = 1;
    opts->disconnect_faststop = true;
    opts->udp_peer_timeout_s = DEFAULT_UDP_PEER_TIMEOUT_S;
    opts->sim_port = -1;
    opts->plant_timeout_ms = HOST_PLANT_TIMEOUT_MS_DEFAULT;
    opts->fingers = "fmf,dsa";
    opts->binary_udp_port = DEFAULT_BINARY_UDP_PORT;
    opts->binary_udp_reply_port = DEFAULT_BINARY_UDP_REPLY_PORT;
    opts->binary_crc = true;
    opts->http_port = DEFAULT_HTTP_PORT;
    opts->http_request_timeout_s = DEFAULT_HTTP_REQUEST_TIMEOUT_S;
    opts->script_autostart = true;
    opts->timing = TIMING_PROFILE_IDEAL;
    opts->seed = DEFAULT_SEED;
}

static options_result_t usage_error(const char *what, const char *value)
{
    fprintf(stderr, "wsgsim: invalid %s '%s' (see --help)\n", what, value);
    return OPTIONS_EXIT_USAGE;
}

/* An integer option within [min, max]; a bad value's error gives the range. */
static options_result_t int_option(const char *name, const char *arg, int min, int max, double *out)
{
    int value = 0;
    if (parse_int(arg, min, max, &value)) {
        *out = value;
        return OPTIONS_RUN;
    }
    fprintf(stderr, "wsgsim: invalid %s '%s': expected an integer from %d to %d\n", name, arg, min,
            max);
    return OPTIONS_EXIT_USAGE;
}

/* A port option; a bad value's error gives the range and what 0 means. */
static options_result_t port_option(const char *name, const char *arg, const char *zero,
                                    double *out)
{
    int value = 0;
    if (parse_int(arg, 0, 65535, &value)) {
        *out = value;
        return OPTIONS_RUN;
    }
    fprintf(stderr, "wsgsim: invalid %s '%s': expected a port from 0 to 65535 (0: %s)\n", name, arg,
            zero);
    return OPTIONS_EXIT_USAGE;
}

/* --model NAME: an unknown name's error lists the models, quoted as a
 * shell needs them (they hold a space). */
static options_result_t model_option(const char *arg)
{
    if (wsg_sim_model_find(arg) != NULL) {
        return OPTIONS_RUN;
    }
    fprintf(stderr, "wsgsim: unknown --model '%s'; the models:", arg);
    for (unsigned i = 0; i < wsg_sim_model_count(); i++) {
        fprintf(stderr, "%s '%s'", i == 0 ? "" : ",", wsg_sim_model_at(i)->name);
    }
    fprintf(stderr, " (--list-models)\n");
    return OPTIONS_EXIT_USAGE;
}

/* Why a --fingers list is refused: the item that is wrong. */
static void fingers_error(const char *list, char *why, size_t cap)
{
    const char *comma = strchr(list, ',');
    if (comma != NULL && strchr(comma + 1, ',') != NULL) {
        snprintf(why, cap, "two fingers at most, one per slot: A,B");
        return;
    }
    char first[32];
    int first_len = comma != NULL ? (int)(comma - list) : (int)strlen(list);
    snprintf(first, sizeof(first), "%.*s", first_len, list);
    fbus_type_t types[FBUS_SLOTS];
    const char *wrong = wsg_finger_node_parse_pair(first, types) ? comma + 1 : first;
    snprintf(why, cap, "'%s' is no finger: each is none, generic, fmf or dsa", wrong);
}

/* --fingers A[,B]: a bad list's error names the item that is wrong. */
static options_result_t fingers_option(const char *arg, host_options_t *opts)
{
    fbus_type_t types[FBUS_SLOTS];
    opts->fingers = arg;
    if (wsg_finger_node_parse_pair(arg, types)) {
        return OPTIONS_RUN;
    }
    char why[96];
    fingers_error(arg, why, sizeof(why));
    fprintf(stderr, "wsgsim: invalid --fingers '%s': %s\n", arg, why);
    return OPTIONS_EXIT_USAGE;
}

/* --http-allow-host: a list of names, one more list each time. */
static options_result_t allow_host_option(const char *arg, const host_options_t *opts)
{
    if (opts->http_allow_host_count == HOST_HTTP_ALLOW_LISTS_MAX) {
        fprintf(stderr, "wsgsim: --http-allow-host may be given at most %d times\n",
                HOST_HTTP_ALLOW_LISTS_MAX);
        return OPTIONS_EXIT_USAGE;
    }
    return http_host_list_valid(arg) ? OPTIONS_RUN : usage_error("--http-allow-host", arg);
}

/* --seed N: 0 to 4294967295. */
static options_result_t seed_option(const char *arg, double *number)
{
    char *end = NULL;
    unsigned long long seed = strtoull(arg, &end, 10);
    if (arg[0] >= '0' && arg[0] <= '9' && *end == '\0' && seed <= 4294967295ull) {
        *number = (double)seed;
        return OPTIONS_RUN;
    }
    fprintf(stderr, "wsgsim: invalid --seed '%s': expected an integer from 0 to 4294967295\n", arg);
    return OPTIONS_EXIT_USAGE;
}

/* --net: wire conditions over the file's; a bad one says what is wrong. */
static options_result_t net_option(const char *arg, const host_options_t *opts)
{
    char why[160];
    wire_spec_t trial = opts->net;
    if (!wire_spec_parse(&trial, arg, why, sizeof(why))) {
        fprintf(stderr, "wsgsim: invalid --net '%s': %s\n", arg, why);
        return OPTIONS_EXIT_USAGE;
    }
    return OPTIONS_RUN;
}

/* How the command line reads an option of option_table.h: its number (a
 * port, seconds, a choice, a switch) with the command line's own errors,
 * or nothing for a text (the argument itself). */
static options_result_t read_table_option(option_id_t id, const char *arg,
                                          const host_options_t *opts, double *number)
{
    host_protocol_t protocol = HOST_PROTOCOL_AUTO;
    switch (id) {
    case OPTION_TCP_PORT:
    case OPTION_UDP_PORT:
    case OPTION_SIM_PORT:
        return port_option(option_table[id].cli, arg, "a free port", number);
    case OPTION_BINARY_UDP_PORT:
    case OPTION_HTTP_PORT:
        return port_option(option_table[id].cli, arg, "off", number);
    case OPTION_BINARY_UDP_REPLY_PORT:
        return port_option(option_table[id].cli, arg, "the sender's own port", number);
    case OPTION_MAX_CLIENTS:
        return int_option(option_table[id].cli, arg, 1, MAX_CLIENTS_LIMIT, number);
    case OPTION_IDLE_TIMEOUT:
        return int_option(option_table[id].cli, arg, 0, TIMEOUT_LIMIT_S, number);
    case OPTION_UDP_PEER_TIMEOUT:
    case OPTION_HTTP_REQUEST_TIMEOUT:
        return int_option(option_table[id].cli, arg, 1, TIMEOUT_LIMIT_S, number);
    case OPTION_PLANT_TIMEOUT:
        return int_option(option_table[id].cli, arg, 1, HOST_MILLISECONDS_MAX, number);
    case OPTION_PROTOCOL:
        *number = options_parse_protocol(arg, &protocol) ? (double)protocol : -1.0;
        return *number >= 0.0 ? OPTIONS_RUN : usage_error("--protocol", arg);
    case OPTION_PHYSICS: {
        host_physics_t physics = HOST_PHYSICS_BUILTIN;
        *number = options_parse_physics(arg, &physics) ? (double)physics : -1.0;
        return *number >= 0.0 ? OPTIONS_RUN : usage_error("--physics", arg);
    }
    case OPTION_MODEL:
        return model_option(arg);
    case OPTION_HTTP_ALLOW_HOST:
        return allow_host_option(arg, opts);
    case OPTION_SEED:
        return seed_option(arg, number);
    case OPTION_ADDRESS_PER_DEVICE:
        *number = 1.0; /* --address-per-device */
        return OPTIONS_RUN;
    case OPTION_NET:
        return net_option(arg, opts);
    default: /* a text, or --no-script-autostart (0) */
        *number = 0.0;
        return OPTIONS_RUN;
    }
}

/* An option the configuration file sets too: read here, written through
 * the same table (option_table.h) the file's value is. The first
 * --udp-stream-allow replaces the file's list, the others add to it. */
static options_result_t apply_table_option(option_id_t id, const char *arg, host_options_t *opts)
{
    double number = 0.0;
    if (id == OPTION_UDP_STREAM_ALLOW && opts->udp_stream_allow_given) {
        return net_allow_add(&opts->udp_stream_allow, arg) ? OPTIONS_RUN
                                                           : usage_error("--udp-stream-allow", arg);
    }
    options_result_t result = read_table_option(id, arg, opts, &number);
    if (result != OPTIONS_RUN) {
        return result;
    }
    opts->udp_stream_allow_given = opts->udp_stream_allow_given || id == OPTION_UDP_STREAM_ALLOW;
    return option_set(opts, id, number, arg) ? OPTIONS_RUN : usage_error(option_table[id].cli, arg);
}

/* The simulation control options (docs/simctl.md) and the binary
 * protocol's checksum switch. */
static options_result_t apply_simctl_option(int opt, const char *arg, host_options_t *opts)
{
    switch (opt) {
    case OPT_CONFIG:
    case OPT_SAVE_FILE:
        return OPTIONS_RUN; /* read before the other options (see options_parse) */
    case OPT_SCENARIO:
        opts->scenario_path = arg;
        return OPTIONS_RUN;
    case OPT_START_PAUSED:
        opts->start_paused = true;
        return OPTIONS_RUN;
    case OPT_RECORD:
        opts->record_path = arg;
        return OPTIONS_RUN;
    case OPT_COVERAGE:
        opts->coverage_path = arg;
        return OPTIONS_RUN;
    case OPT_STRICT:
        opts->strict = true;
        return OPTIONS_RUN;
    case OPT_BINARY_NO_CRC:
        opts->binary_crc = false;
        return OPTIONS_RUN;
    default:
        return OPTIONS_EXIT_USAGE;
    }
}

/* Logging, supervision and listing options. */
static options_result_t apply_service_option(int opt, const char *arg, host_options_t *opts)
{
    switch (opt) {
    case OPT_LOG_LEVEL:
        return host_log_parse_level(arg, &opts->log_level) ? OPTIONS_RUN
                                                           : usage_error("--log-level", arg);
    case OPT_QUIET:
        opts->log_level = HAL_LOG_ERROR;
        return OPTIONS_RUN;
    case OPT_LOG_TIMESTAMPS:
        opts->log_timestamps = true;
        return OPTIONS_RUN;
    case OPT_LOG_FILE:
        opts->log_file = arg;
        return OPTIONS_RUN;
    case OPT_READY_FILE:
        opts->ready_file = arg;
        return OPTIONS_RUN;
    case OPT_CAN_LOG:
        opts->can_log = arg;
        return OPTIONS_RUN;
    case OPT_LIST_MODELS:
        opts->list_models = true;
        return OPTIONS_RUN;
    case OPT_JSON:
        opts->list_models_json = true;
        return OPTIONS_RUN;
    default:
        return apply_simctl_option(opt, arg, opts);
    }
}

/* getopt's own messages name argv[0] (a path when installed): these name
 * the program, in the one style of every wsgsim error. */
static options_result_t unknown_option(int opt, char **argv)
{
    const char *given = argv[optind - 1];
    if (opt == ':') {
        fprintf(stderr, "wsgsim: option '%s' needs an argument (see --help)\n", given);
    } else if (given[1] != '-') {
        fprintf(stderr, "wsgsim: unknown option '-%c' (see --help)\n", optopt);
    } else {
        fprintf(stderr, "wsgsim: unknown option '%s' (see --help)\n", given);
    }
    return OPTIONS_EXIT_USAGE;
}

/* The value of the last "--name FILE" or "--name=FILE" in argv, or NULL. */
static const char *file_option(int argc, char **argv, const char *name)
{
    const char *path = NULL;
    size_t len = strlen(name);
    for (int i = 1; i < argc; i++) {
        if (strcmp(argv[i], name) == 0 && i + 1 < argc) {
            path = argv[++i];
        } else if (strncmp(argv[i], name, len) == 0 && argv[i][len] == '=') {
            path = argv[i] + len + 1;
        }
    }
    return path;
}

/* --config FILE and --save-file FILE are read first so that every other
 * option overrides them. */
static bool load_config(int argc, char **argv, host_options_t *opts)
{
    opts->config_path = file_option(argc, argv, "--config");
    opts->save_path = file_option(argc, argv, "--save-file");
    if (opts->config_path == NULL && opts->save_path == NULL) {
        return true;
    }
    opts->config = config_file_create();
    if (opts->config == NULL) {
        fprintf(stderr, "wsgsim: out of memory\n");
        return false;
    }
    return config_file_load(opts->config, opts->config_path, opts->save_path, opts);
}

/* Applies one option; returns OPTIONS_RUN to go on. */
static options_result_t apply_option(int opt, const char *arg, host_options_t *opts)
{
    double devices = 0.0;
    if (opt >= OPT_TABLE && opt < OPT_TABLE + OPTION_COUNT) {
        return apply_table_option((option_id_t)(opt - OPT_TABLE), arg, opts);
    }
    switch (opt) {
    case OPT_NO_TCP:
        opts->tcp_enabled = false;
        return OPTIONS_RUN;
    case OPT_NO_UDP:
        opts->udp_enabled = false;
        return OPTIONS_RUN;
    case OPT_PART:
        return parse_part(arg, opts) ? OPTIONS_RUN : usage_error("--part", arg);
    case OPT_DEVICES:
        if (int_option("--devices", arg, 1, HOST_DEVICES_MAX, &devices) != OPTIONS_RUN) {
            return OPTIONS_EXIT_USAGE;
        }
        opts->devices = (int)devices;
        return OPTIONS_RUN;
    case OPT_NO_DISCONNECT_FASTSTOP:
        opts->disconnect_faststop = false;
        return OPTIONS_RUN;
    case OPT_TRACE:
        opts->trace = true;
        return OPTIONS_RUN;
    case OPT_CAN:
        opts->can_iface = arg;
        return OPTIONS_RUN;
    case OPT_FINGERS:
        return fingers_option(arg, opts);
    case OPT_VERSION:
        printf("wsgsim %s (GCL firmware 4.0)\n", WSGSIM_VERSION);
        return OPTIONS_EXIT_OK;
    case OPT_HELP:
        options_print_help();
        return OPTIONS_EXIT_OK;
    default:
        return apply_service_option(opt, arg, opts);
    }
}

/* The profile --timing (or [timing] profile) names, read once. */
static options_result_t read_timing(host_options_t *opts)
{
    char why[TIMING_WHY_MAX];
    if (!timing_profile_load(opts->timing, &opts->timing_figures, why)) {
        fprintf(stderr, "wsgsim: --timing: %s\n", why);
        return OPTIONS_EXIT_USAGE;
    }
    return OPTIONS_RUN;
}

static options_result_t check_combinations(host_options_t *opts)
{
    if (opts->list_models) {
        options_list_models(opts->list_models_json);
        return OPTIONS_EXIT_OK;
    }
    if (opts->list_models_json) {
        fprintf(stderr, "wsgsim: --json goes with --list-models\n");
        return OPTIONS_EXIT_USAGE;
    }
    if (opts->can_log != NULL && opts->can_iface != NULL) {
        fprintf(stderr,
                "wsgsim: --can-log records the in-process bus; with --can %s use "
                "candump -L %s\n",
                opts->can_iface, opts->can_iface);
        return OPTIONS_EXIT_USAGE;
    }
    if (!opts->tcp_enabled && !opts->udp_enabled) {
        fprintf(stderr, "wsgsim: --no-tcp and --no-udp leave nothing to serve\n");
        return OPTIONS_EXIT_USAGE;
    }
    if ((opts->config_path != NULL || opts->save_path != NULL) &&
        !config_file_check(opts->config, opts->model)) {
        return OPTIONS_EXIT_USAGE;
    }
    if (!script_options_check(opts)) {
        return OPTIONS_EXIT_USAGE;
    }
    return read_timing(opts);
}

void options_release(host_options_t *opts)
{
    config_file_destroy(opts->config);
    opts->config = NULL;
}

options_result_t options_parse(int argc, char **argv, host_options_t *opts)
{
    set_defaults(opts);
    if (!load_config(argc, argv, opts)) {
        return OPTIONS_EXIT_USAGE;
    }
    int opt;
    optind = 1;
    opterr = 0;
    while ((opt = getopt_long(argc, argv, SHORT_OPTIONS, long_options, NULL)) != -1) {
        if (opt == '?' || opt == ':') {
            return unknown_option(opt, argv);
        }
        options_result_t result = apply_option(opt, optarg, opts);
        if (result != OPTIONS_RUN) {
            return result;
        }
    }
    if (optind < argc) {
        return usage_error("argument", argv[optind]);
    }
    if (!opts->udp_port_given) { /* the device serves both on one port */
        opts->udp_port = opts->tcp_port;
    }
    return check_combinations(opts);
}
