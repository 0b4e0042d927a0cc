/* SPDX-License-Identifier: BSD-3-Clause */
#include "options.h"

#include <cjson/cJSON.h>
#include <getopt.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "config_file.h"
#include "log.h"
#include "script_options.h"
#include "sim/finger_node.h"
#include "sim/sim_models.h"
#include "version.h"
#include "http_host.h"

#define DEFAULT_PORT 1000
#define DEFAULT_MAX_CLIENTS 8
#define MAX_CLIENTS_LIMIT 128
#define DEFAULT_PART_STIFFNESS 100.0f
#define DEFAULT_UDP_PEER_TIMEOUT_S 60
#define DEFAULT_BINARY_UDP_PORT 1500
#define DEFAULT_BINARY_UDP_REPLY_PORT 1501
#define DEFAULT_HTTP_PORT 8080
#define DEFAULT_HTTP_REQUEST_TIMEOUT_S 10
#define TIMEOUT_LIMIT_S 86400

static void print_help(void)
{
    printf("Usage: wsgsim [OPTION]...\n"
           "A virtual Weiss Robotics WSG gripper serving GCL on TCP and UDP.\n\n"
           "  --tcp-port N               TCP port (default %d)\n"
           "  --udp-port N               UDP port (default: the TCP port, %d unless\n"
           "                             --tcp-port moves it)\n"
           "  --no-tcp                   do not serve TCP\n"
           "  --no-udp                   do not serve UDP\n"
           "  --bind ADDR                listen address: IPv4, IPv6 or a host name such as\n"
           "                             localhost (default 0.0.0.0; :: serves IPv6 and IPv4)\n"
           "  --devices N                serve N independent grippers (1..%d); device i on\n"
           "                             TCP and UDP port + i (port 0: free ports each);\n"
           "                             with the default binary ports, binary UDP on\n"
           "                             1500 + 2i replying to 1501 + 2i (moved past the\n"
           "                             UDP ports when these reach 1500)\n"
           "  --address-per-device       with --devices: device i on the --bind address + i\n"
           "                             (IPv4, e.g. 127.1.0.1, 127.1.0.2, ...) at the same\n"
           "                             ports, one socket per protocol for all devices\n"
           "  --model NAME               gripper model (default %s; see --list-models)\n"
           "  --list-models              list the simulated models and exit\n"
           "  --json                     with --list-models: print the list as JSON\n"
           "  --part W[:K]               a part of width W mm (stiffness K N/mm, default %.0f)\n"
           "                             between the jaws at start\n"
           "  --max-clients N            simultaneous TCP clients (default %d, at most %d)\n"
           "  --no-disconnect-faststop   a connection closed without BYE() does not raise\n"
           "                             FAST STOP\n"
           "  --idle-timeout S           close a TCP connection that sent nothing for S\n"
           "                             simulated seconds (default: never)\n"
           "  --udp-peer-timeout S       forget a UDP peer (and end its AUTOSEND) after S\n"
           "                             simulated seconds without a datagram (default %d)\n"
           "  --udp-stream-allow A[/P]   UDP peers at these addresses (comma-separated,\n"
           "                             repeatable) keep AUTOSEND and automatic updates\n"
           "                             while silent, as loopback peers always do; other\n"
           "                             peers' streams are paid by what they send\n"
           "                             (default: none)\n"
           "  --trace                    log every line in and out on stderr\n"
           "  --can IFACE                finger bus on the SocketCAN interface IFACE (e.g.\n"
           "                             vcan0; run tools/fingersim there); default: an\n"
           "                             in-process bus with simulated fingers\n"
           "  --fingers A[,B]            fingers on the in-process bus, each none, generic,\n"
           "                             fmf or dsa (default fmf,dsa)\n"
           "  --can-log FILE             write every frame of the in-process bus to FILE in\n"
           "                             candump -L format (simulated time stamps)\n"
           "  --config FILE              device configuration (INI); options override it;\n"
           "                             every key: " WSGSIM_EXAMPLE_CONFIG "\n"
           "  --save-file FILE           where the web page's Save writes the settings\n"
           "                             (default: the --config file); read over the\n"
           "                             --config file at start when it exists\n"
           "  --sim-port N               simulation control channel on TCP port N\n"
           "                             (docs/simctl.md; 0 picks a free port)\n"
           "  --sim-bind ADDR            control channel address (default 127.0.0.1)\n"
           "  --scenario FILE            run timed control commands on the simulated clock\n"
           "  --start-paused             start with the simulated clock paused at 0\n"
           "  --record FILE              record every line in and out with timestamps, and\n"
           "                             the device's state while it moves (tools/wsgplot)\n"
           "  --coverage FILE            write a protocol coverage report at exit\n"
           "  --strict                   report input the manual does not allow but the\n"
           "                             emulator tolerates (coverage report and trace)\n"
           "  --protocol P               what TCP connections speak: auto (default: a first\n"
           "                             byte 0xAA is the binary protocol, else GCL), gcl\n"
           "                             or binary\n"
           "  --binary-udp-port N        binary protocol over UDP on port N (default 1500;\n"
           "                             0: off; the default is skipped when taken)\n"
           "  --binary-udp-reply-port N  binary UDP replies go to the sender's address at\n"
           "                             port N (default 1501; 0: the sender's own port)\n"
           "  --binary-no-crc            binary requests' checksums are read and ignored\n"
           "  --http-port N              web interface (page and JSON API, docs/web.md) on\n"
           "                             TCP port N (default %d; 0: off; the default is\n"
           "                             skipped when taken)\n"
           "  --http-bind ADDR           web interface address (default: as --bind); its\n"
           "                             simulation panel serves loopback clients only\n"
           "                             unless --sim-bind names another address\n"
           "  --http-allow-host NAME[,NAME]...\n"
           "                             names the web interface answers to besides its\n"
           "                             IP addresses and localhost (a Host header with\n"
           "                             another name is refused: DNS rebinding); may be\n"
           "                             repeated; * allows every name\n"
           "  --http-request-timeout S   close a web connection whose request (header and\n"
           "                             body) has not fully arrived S wall-clock seconds\n"
           "                             after it opened or its last reply (default %d)\n"
           "  --log-level LEVEL          log error, warn, info or debug messages and above\n"
           "                             (default info)\n"
           "  --quiet                    log errors only (--log-level error)\n"
           "  --log-timestamps           start each log line with the wall-clock time\n"
           "                             (ISO 8601, UTC)\n"
           "  --log-file FILE            log to FILE (appending) instead of stderr; SIGHUP\n"
           "                             reopens it and the --record and --can-log files\n"
           "  --ready-file FILE          once serving, write pid and ports to FILE\n"
           "                             (removed at exit); under systemd, wsgsim also\n"
           "                             reports READY=1 (Type=notify)\n"
           "  --script FILE              run the Lua script FILE (a path, or /user/NAME in\n"
           "                             the store) at power-on and after RESET()\n"
           "  --script-dir DIR           the script store, the device's /user/ (default:\n"
           "                             the --script file's directory)\n"
           "  --no-script-autostart      keep --script selected but do not run it\n"
           "  -V, --version              print the version and exit\n"
           "  -h, --help                 print this help and exit\n",
           DEFAULT_PORT, DEFAULT_PORT, HOST_DEVICES_MAX, wsg_sim_model_default()->name,
           (double)DEFAULT_PART_STIFFNESS, DEFAULT_MAX_CLIENTS, MAX_CLIENTS_LIMIT,
           DEFAULT_UDP_PEER_TIMEOUT_S, DEFAULT_HTTP_PORT, DEFAULT_HTTP_REQUEST_TIMEOUT_S);
}

static void list_models_json(void)
{
    cJSON *list = cJSON_CreateArray();
    for (unsigned i = 0; list != NULL && i < wsg_sim_model_count(); i++) {
        const sim_model_t *m = wsg_sim_model_at(i);
        cJSON *o = cJSON_CreateObject();
        cJSON_AddStringToObject(o, "name", m->name);
        cJSON_AddBoolToObject(o, "default", m == wsg_sim_model_default());
        cJSON_AddNumberToObject(o, "stroke_mm", (double)m->stroke_mm);
        cJSON_AddNumberToObject(o, "speed_min_mm_s", (double)m->speed_min_mm_s);
        cJSON_AddNumberToObject(o, "speed_max_mm_s", (double)m->speed_max_mm_s);
        cJSON_AddNumberToObject(o, "accel_min_mm_s2", (double)m->accel_min_mm_s2);
        cJSON_AddNumberToObject(o, "accel_max_mm_s2", (double)m->accel_max_mm_s2);
        cJSON_AddNumberToObject(o, "force_min_n", (double)m->force_min_n);
        cJSON_AddNumberToObject(o, "force_max_n", (double)m->force_max_n);
        cJSON_AddBoolToObject(o, "estimated", m->estimated);
        cJSON_AddItemToArray(list, o);
    }
    char *text = cJSON_PrintUnformatted(list);
    if (text != NULL) {
        printf("%s\n", text);
    }
    cJSON_free(text);
    cJSON_Delete(list);
}

static void list_models_text(void)
{
    for (unsigned i = 0; i < wsg_sim_model_count(); i++) {
        const sim_model_t *m = wsg_sim_model_at(i);
        printf("%-12s stroke %.0f mm, speed %.0f-%.0f mm/s, accel %.0f-%.0f mm/s^2, "
               "force %.0f-%.0f N%s\n",
               m->name, (double)m->stroke_mm, (double)m->speed_min_mm_s, (double)m->speed_max_mm_s,
               (double)m->accel_min_mm_s2, (double)m->accel_max_mm_s2, (double)m->force_min_n,
               (double)m->force_max_n, m->estimated ? " (estimated figures)" : "");
    }
}

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

enum {
    OPT_TCP_PORT = 256,
    OPT_UDP_PORT,
    OPT_NO_TCP,
    OPT_NO_UDP,
    OPT_BIND,
    OPT_MODEL,
    OPT_LIST_MODELS,
    OPT_PART,
    OPT_MAX_CLIENTS,
    OPT_DEVICES,
    OPT_NO_DISCONNECT_FASTSTOP,
    OPT_IDLE_TIMEOUT,
    OPT_UDP_PEER_TIMEOUT,
    OPT_UDP_STREAM_ALLOW,
    OPT_TRACE,
    OPT_CAN,
    OPT_FINGERS,
    OPT_CONFIG,
    OPT_SAVE_FILE,
    OPT_SIM_PORT,
    OPT_SIM_BIND,
    OPT_SCENARIO,
    OPT_START_PAUSED,
    OPT_RECORD,
    OPT_COVERAGE,
    OPT_STRICT,
    OPT_PROTOCOL,
    OPT_BINARY_UDP_PORT,
    OPT_BINARY_UDP_REPLY_PORT,
    OPT_BINARY_NO_CRC,
    OPT_HTTP_PORT,
    OPT_HTTP_BIND,
    OPT_HTTP_ALLOW_HOST,
    OPT_HTTP_REQUEST_TIMEOUT,
    OPT_JSON,
    OPT_CAN_LOG,
    OPT_LOG_LEVEL,
    OPT_QUIET,
    OPT_LOG_TIMESTAMPS,
    OPT_LOG_FILE,
    OPT_READY_FILE,
    OPT_SCRIPT,
    OPT_SCRIPT_DIR,
    OPT_NO_SCRIPT_AUTOSTART,
    OPT_ADDRESS_PER_DEVICE,
    OPT_VERSION = 'V',
    OPT_HELP = 'h',
};
#define SHORT_OPTIONS ":hV" /* leading ':': a missing argument returns ':' */

static const struct option long_options[] = {
    {"tcp-port", required_argument, NULL, OPT_TCP_PORT},
    {"udp-port", required_argument, NULL, OPT_UDP_PORT},
    {"no-tcp", no_argument, NULL, OPT_NO_TCP},
    {"no-udp", no_argument, NULL, OPT_NO_UDP},
    {"bind", required_argument, NULL, OPT_BIND},
    {"model", required_argument, NULL, OPT_MODEL},
    {"list-models", no_argument, NULL, OPT_LIST_MODELS},
    {"part", required_argument, NULL, OPT_PART},
    {"max-clients", required_argument, NULL, OPT_MAX_CLIENTS},
    {"devices", required_argument, NULL, OPT_DEVICES},
    {"address-per-device", no_argument, NULL, OPT_ADDRESS_PER_DEVICE},
    {"no-disconnect-faststop", no_argument, NULL, OPT_NO_DISCONNECT_FASTSTOP},
    {"idle-timeout", required_argument, NULL, OPT_IDLE_TIMEOUT},
    {"udp-peer-timeout", required_argument, NULL, OPT_UDP_PEER_TIMEOUT},
    {"udp-stream-allow", required_argument, NULL, OPT_UDP_STREAM_ALLOW},
    {"trace", no_argument, NULL, OPT_TRACE},
    {"can", required_argument, NULL, OPT_CAN},
    {"fingers", required_argument, NULL, OPT_FINGERS},
    {"config", required_argument, NULL, OPT_CONFIG},
    {"save-file", required_argument, NULL, OPT_SAVE_FILE},
    {"sim-port", required_argument, NULL, OPT_SIM_PORT},
    {"sim-bind", required_argument, NULL, OPT_SIM_BIND},
    {"scenario", required_argument, NULL, OPT_SCENARIO},
    {"start-paused", no_argument, NULL, OPT_START_PAUSED},
    {"record", required_argument, NULL, OPT_RECORD},
    {"coverage", required_argument, NULL, OPT_COVERAGE},
    {"strict", no_argument, NULL, OPT_STRICT},
    {"protocol", required_argument, NULL, OPT_PROTOCOL},
    {"binary-udp-port", required_argument, NULL, OPT_BINARY_UDP_PORT},
    {"binary-udp-reply-port", required_argument, NULL, OPT_BINARY_UDP_REPLY_PORT},
    {"binary-no-crc", no_argument, NULL, OPT_BINARY_NO_CRC},
    {"http-port", required_argument, NULL, OPT_HTTP_PORT},
    {"http-bind", required_argument, NULL, OPT_HTTP_BIND},
    {"http-allow-host", required_argument, NULL, OPT_HTTP_ALLOW_HOST},
    {"http-request-timeout", required_argument, NULL, OPT_HTTP_REQUEST_TIMEOUT},
    {"json", no_argument, NULL, OPT_JSON},
    {"can-log", required_argument, NULL, OPT_CAN_LOG},
    {"log-level", required_argument, NULL, OPT_LOG_LEVEL},
    {"quiet", no_argument, NULL, OPT_QUIET},
    {"log-timestamps", no_argument, NULL, OPT_LOG_TIMESTAMPS},
    {"log-file", required_argument, NULL, OPT_LOG_FILE},
    {"ready-file", required_argument, NULL, OPT_READY_FILE},
    {"script", required_argument, NULL, OPT_SCRIPT},
    {"script-dir", required_argument, NULL, OPT_SCRIPT_DIR},
    {"no-script-autostart", no_argument, NULL, OPT_NO_SCRIPT_AUTOSTART},
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
    opts->fingers = "fmf,dsa";
    opts->binary_udp_port = DEFAULT_BINARY_UDP_PORT;
    opts->binary_udp_reply_port = DEFAULT_BINARY_UDP_REPLY_PORT;
    opts->binary_crc = true;
    opts->http_port = DEFAULT_HTTP_PORT;
    opts->http_request_timeout_s = DEFAULT_HTTP_REQUEST_TIMEOUT_S;
    opts->script_autostart = true;
}

static options_result_t usage_error(const char *what, const char *value);
static options_result_t int_option(const char *name, const char *arg, int min, int max, int *out);
static options_result_t port_option(const char *name, const char *arg, const char *zero, int *out);

/* The web interface's admission options (docs/web.md, "Who is served"). */
static options_result_t apply_web_option(int opt, const char *arg, host_options_t *opts)
{
    switch (opt) {
    case OPT_HTTP_ALLOW_HOST:
        if (opts->http_allow_host_count == HOST_HTTP_ALLOW_LISTS_MAX) {
            fprintf(stderr, "wsgsim: --http-allow-host may be given at most %d times\n",
                    HOST_HTTP_ALLOW_LISTS_MAX);
            return OPTIONS_EXIT_USAGE;
        }
        if (!http_host_list_valid(arg)) {
            return usage_error("--http-allow-host", arg);
        }
        opts->http_allow_hosts[opts->http_allow_host_count++] = arg;
        return OPTIONS_RUN;
    case OPT_HTTP_REQUEST_TIMEOUT:
        return int_option("--http-request-timeout", arg, 1, TIMEOUT_LIMIT_S,
                          &opts->http_request_timeout_s);
    default:
        return OPTIONS_EXIT_USAGE;
    }
}

/* The binary protocol's options (docs/binary-protocol.md) and the web
 * interface's (docs/web.md): the other ways in besides GCL. */
static options_result_t apply_binary_option(int opt, const char *arg, host_options_t *opts)
{
    switch (opt) {
    case OPT_PROTOCOL:
        return options_parse_protocol(arg, &opts->protocol) ? OPTIONS_RUN
                                                            : usage_error("--protocol", arg);
    case OPT_BINARY_UDP_PORT:
        opts->binary_udp_port_given = true;
        return port_option("--binary-udp-port", arg, "off", &opts->binary_udp_port);
    case OPT_BINARY_UDP_REPLY_PORT:
        return port_option("--binary-udp-reply-port", arg, "the sender's own port",
                           &opts->binary_udp_reply_port);
    case OPT_BINARY_NO_CRC:
        opts->binary_crc = false;
        return OPTIONS_RUN;
    case OPT_HTTP_PORT:
        opts->http_port_given = true;
        return port_option("--http-port", arg, "off", &opts->http_port);
    case OPT_HTTP_BIND:
        opts->http_bind = arg;
        return OPTIONS_RUN;
    default:
        return OPTIONS_EXIT_USAGE;
    }
}

static options_result_t usage_error(const char *what, const char *value)
{
    fprintf(stderr, "wsgsim: invalid %s '%s' (see --help)\n", what, value);
    return OPTIONS_EXIT_USAGE;
}

/* An integer option within [min, max]; a bad value's error gives the range. */
static options_result_t int_option(const char *name, const char *arg, int min, int max, int *out)
{
    if (parse_int(arg, min, max, out)) {
        return OPTIONS_RUN;
    }
    fprintf(stderr, "wsgsim: invalid %s '%s': expected an integer from %d to %d\n", name, arg, min,
            max);
    return OPTIONS_EXIT_USAGE;
}

/* A port option; a bad value's error gives the range and what 0 means. */
static options_result_t port_option(const char *name, const char *arg, const char *zero, int *out)
{
    if (parse_int(arg, 0, 65535, out)) {
        return OPTIONS_RUN;
    }
    fprintf(stderr, "wsgsim: invalid %s '%s': expected a port from 0 to 65535 (0: %s)\n", name, arg,
            zero);
    return OPTIONS_EXIT_USAGE;
}

/* --model NAME: an unknown name's error lists the models, quoted as a
 * shell needs them (they hold a space). */
static options_result_t model_option(const char *arg, host_options_t *opts)
{
    opts->model = arg;
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

/* The simulation control options (docs/simctl.md). */
static options_result_t apply_simctl_option(int opt, const char *arg, host_options_t *opts)
{
    switch (opt) {
    case OPT_CONFIG:
    case OPT_SAVE_FILE:
        return OPTIONS_RUN; /* read before the other options (see options_parse) */
    case OPT_SIM_PORT:
        return port_option("--sim-port", arg, "a free port", &opts->sim_port);
    case OPT_SIM_BIND:
        opts->sim_bind = arg;
        return OPTIONS_RUN;
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
        return OPTIONS_EXIT_USAGE;
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
    switch (opt) {
    case OPT_TCP_PORT:
        return port_option("--tcp-port", arg, "a free port", &opts->tcp_port);
    case OPT_UDP_PORT:
        opts->udp_port_given = true;
        return port_option("--udp-port", arg, "a free port", &opts->udp_port);
    case OPT_NO_TCP:
        opts->tcp_enabled = false;
        return OPTIONS_RUN;
    case OPT_NO_UDP:
        opts->udp_enabled = false;
        return OPTIONS_RUN;
    case OPT_BIND:
        opts->bind_addr = arg;
        return OPTIONS_RUN;
    case OPT_MODEL:
        return model_option(arg, opts);
    case OPT_PART:
        return parse_part(arg, opts) ? OPTIONS_RUN : usage_error("--part", arg);
    case OPT_DEVICES:
        return int_option("--devices", arg, 1, HOST_DEVICES_MAX, &opts->devices);
    case OPT_ADDRESS_PER_DEVICE:
        opts->address_per_device = true;
        return OPTIONS_RUN;
    case OPT_MAX_CLIENTS:
        return int_option("--max-clients", arg, 1, MAX_CLIENTS_LIMIT, &opts->max_clients);
    case OPT_NO_DISCONNECT_FASTSTOP:
        opts->disconnect_faststop = false;
        return OPTIONS_RUN;
    case OPT_IDLE_TIMEOUT:
        return int_option("--idle-timeout", arg, 0, TIMEOUT_LIMIT_S, &opts->idle_timeout_s);
    case OPT_UDP_PEER_TIMEOUT:
        return int_option("--udp-peer-timeout", arg, 1, TIMEOUT_LIMIT_S, &opts->udp_peer_timeout_s);
    case OPT_UDP_STREAM_ALLOW:
        if (!opts->udp_stream_allow_given) {
            opts->udp_stream_allow.count = 0;
            opts->udp_stream_allow_given = true;
        }
        return net_allow_add(&opts->udp_stream_allow, arg) ? OPTIONS_RUN
                                                           : usage_error("--udp-stream-allow", arg);
    case OPT_TRACE:
        opts->trace = true;
        return OPTIONS_RUN;
    case OPT_CAN:
        opts->can_iface = arg;
        return OPTIONS_RUN;
    case OPT_FINGERS:
        return fingers_option(arg, opts);
    case OPT_CONFIG:
    case OPT_SAVE_FILE:
    case OPT_SIM_PORT:
    case OPT_SIM_BIND:
    case OPT_SCENARIO:
    case OPT_START_PAUSED:
    case OPT_RECORD:
    case OPT_COVERAGE:
    case OPT_STRICT:
        return apply_simctl_option(opt, arg, opts);
    case OPT_PROTOCOL:
    case OPT_BINARY_UDP_PORT:
    case OPT_BINARY_UDP_REPLY_PORT:
    case OPT_BINARY_NO_CRC:
    case OPT_HTTP_PORT:
    case OPT_HTTP_BIND:
        return apply_binary_option(opt, arg, opts);
    case OPT_HTTP_ALLOW_HOST:
    case OPT_HTTP_REQUEST_TIMEOUT:
        return apply_web_option(opt, arg, opts);
    case OPT_LOG_LEVEL:
    case OPT_QUIET:
    case OPT_LOG_TIMESTAMPS:
    case OPT_LOG_FILE:
    case OPT_READY_FILE:
    case OPT_CAN_LOG:
    case OPT_LIST_MODELS:
    case OPT_JSON:
        return apply_service_option(opt, arg, opts);
    case OPT_SCRIPT:
        opts->script = arg;
        return OPTIONS_RUN;
    case OPT_SCRIPT_DIR:
        opts->script_dir = arg;
        return OPTIONS_RUN;
    case OPT_NO_SCRIPT_AUTOSTART:
        opts->script_autostart = false;
        return OPTIONS_RUN;
    case OPT_VERSION:
        printf("wsgsim %s (GCL firmware 4.0)\n", WSGSIM_VERSION);
        return OPTIONS_EXIT_OK;
    case OPT_HELP:
        print_help();
        return OPTIONS_EXIT_OK;
    default:
        return OPTIONS_EXIT_USAGE;
    }
}

static options_result_t check_combinations(const host_options_t *opts)
{
    if (opts->list_models) {
        if (opts->list_models_json) {
            list_models_json();
        } else {
            list_models_text();
        }
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
    return OPTIONS_RUN;
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
