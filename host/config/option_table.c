/* SPDX-License-Identifier: BSD-3-Clause */
#include "option_table.h"

static bool set_model(host_options_t *opts, double number, const char *text)
{
    (void)number;
    opts->model = text;
    return true;
}

static bool set_tcp_port(host_options_t *opts, double number, const char *text)
{
    (void)text;
    opts->tcp_port = (int)number;
    return true;
}

/* Given, the UDP port no longer follows the TCP port. */
static bool set_udp_port(host_options_t *opts, double number, const char *text)
{
    (void)text;
    opts->udp_port = (int)number;
    opts->udp_port_given = true;
    return true;
}

static bool set_bind(host_options_t *opts, double number, const char *text)
{
    (void)number;
    opts->bind_addr = text;
    return true;
}

static bool set_max_clients(host_options_t *opts, double number, const char *text)
{
    (void)text;
    opts->max_clients = (int)number;
    return true;
}

static bool set_address_per_device(host_options_t *opts, double number, const char *text)
{
    (void)text;
    opts->address_per_device = number != 0.0;
    return true;
}

static bool set_idle_timeout(host_options_t *opts, double number, const char *text)
{
    (void)text;
    opts->idle_timeout_s = (int)number;
    return true;
}

static bool set_udp_peer_timeout(host_options_t *opts, double number, const char *text)
{
    (void)text;
    opts->udp_peer_timeout_s = (int)number;
    return true;
}

/* The list is replaced by this one (the command line's first
 * --udp-stream-allow replaces the file's; its others add to it). */
static bool set_udp_stream_allow(host_options_t *opts, double number, const char *text)
{
    (void)number;
    opts->udp_stream_allow.count = 0;
    return net_allow_add(&opts->udp_stream_allow, text);
}

static bool set_sim_port(host_options_t *opts, double number, const char *text)
{
    (void)text;
    opts->sim_port = (int)number;
    return true;
}

static bool set_sim_bind(host_options_t *opts, double number, const char *text)
{
    (void)number;
    opts->sim_bind = text;
    return true;
}

static bool set_protocol(host_options_t *opts, double number, const char *text)
{
    (void)text;
    opts->protocol = (host_protocol_t)number;
    return true;
}

/* Given, a binary UDP port that cannot be had is an error. */
static bool set_binary_udp_port(host_options_t *opts, double number, const char *text)
{
    (void)text;
    opts->binary_udp_port = (int)number;
    opts->binary_udp_port_given = true;
    return true;
}

static bool set_binary_udp_reply_port(host_options_t *opts, double number, const char *text)
{
    (void)text;
    opts->binary_udp_reply_port = (int)number;
    return true;
}

/* Given, a web port that cannot be had is an error. */
static bool set_http_port(host_options_t *opts, double number, const char *text)
{
    (void)text;
    opts->http_port = (int)number;
    opts->http_port_given = true;
    return true;
}

static bool set_http_bind(host_options_t *opts, double number, const char *text)
{
    (void)number;
    opts->http_bind = text;
    return true;
}

/* One more list of names (the file's first, then each option's). */
static bool set_http_allow_host(host_options_t *opts, double number, const char *text)
{
    (void)number;
    if (opts->http_allow_host_count == HOST_HTTP_ALLOW_LISTS_MAX) {
        return false;
    }
    opts->http_allow_hosts[opts->http_allow_host_count++] = text;
    return true;
}

static bool set_http_request_timeout(host_options_t *opts, double number, const char *text)
{
    (void)text;
    opts->http_request_timeout_s = (int)number;
    return true;
}

static bool set_script(host_options_t *opts, double number, const char *text)
{
    (void)number;
    opts->script = text;
    return true;
}

static bool set_script_dir(host_options_t *opts, double number, const char *text)
{
    (void)number;
    opts->script_dir = text;
    return true;
}

static bool set_script_autostart(host_options_t *opts, double number, const char *text)
{
    (void)text;
    opts->script_autostart = number != 0.0;
    return true;
}

static bool set_timing(host_options_t *opts, double number, const char *text)
{
    (void)number;
    opts->timing = text;
    return true;
}

static bool set_seed(host_options_t *opts, double number, const char *text)
{
    (void)text;
    opts->seed = (uint32_t)number;
    return true;
}

static bool set_physics(host_options_t *opts, double number, const char *text)
{
    opts->physics = (host_physics_t)number;
    opts->plant_socket =
        opts->physics == HOST_PHYSICS_SOCKET ? text + strlen(HOST_PHYSICS_SOCKET_PREFIX) : NULL;
    return true;
}

static bool set_scene(host_options_t *opts, double number, const char *text)
{
    (void)number;
    opts->scene = text;
    return true;
}

/* Applied over what the file set: "--net loss=0.1" adds to its conditions,
 * a preset first replaces them. The text was checked (CV_NET). */
static bool set_net(host_options_t *opts, double number, const char *text)
{
    char why[160];
    (void)number;
    return wire_spec_parse(&opts->net, text, why, sizeof(why));
}

static bool set_plant_timeout(host_options_t *opts, double number, const char *text)
{
    (void)text;
    opts->plant_timeout_ms = (unsigned)number;
    return true;
}

const option_row_t option_table[OPTION_COUNT] = {
    [OPTION_MODEL] = {"--model", "device", "model", CV_MODEL, set_model},
    [OPTION_TCP_PORT] = {"--tcp-port", "network", "tcp_port", CV_PORT, set_tcp_port},
    [OPTION_UDP_PORT] = {"--udp-port", "network", "udp_port", CV_PORT, set_udp_port},
    [OPTION_BIND] = {"--bind", "network", "bind", CV_ADDR, set_bind},
    [OPTION_MAX_CLIENTS] = {"--max-clients", "network", "max_clients", CV_CLIENTS, set_max_clients},
    [OPTION_ADDRESS_PER_DEVICE] = {"--address-per-device", "network", "address_per_device", CV_BOOL,
                                   set_address_per_device},
    [OPTION_IDLE_TIMEOUT] = {"--idle-timeout", "network", "idle_timeout", CV_SECONDS_OFF,
                             set_idle_timeout},
    [OPTION_UDP_PEER_TIMEOUT] = {"--udp-peer-timeout", "network", "udp_peer_timeout", CV_SECONDS,
                                 set_udp_peer_timeout},
    [OPTION_UDP_STREAM_ALLOW] = {"--udp-stream-allow", "network", "udp_stream_allow", CV_ALLOW,
                                 set_udp_stream_allow},
    [OPTION_SIM_PORT] = {"--sim-port", "network", "sim_port", CV_PORT_OFF, set_sim_port},
    [OPTION_SIM_BIND] = {"--sim-bind", "network", "sim_bind", CV_LOOPBACK, set_sim_bind},
    [OPTION_PROTOCOL] = {"--protocol", "network", "protocol", CV_PROTOCOL, set_protocol},
    [OPTION_BINARY_UDP_PORT] = {"--binary-udp-port", "network", "binary_udp_port", CV_PORT,
                                set_binary_udp_port},
    [OPTION_BINARY_UDP_REPLY_PORT] = {"--binary-udp-reply-port", "network", "binary_udp_reply_port",
                                      CV_PORT, set_binary_udp_reply_port},
    [OPTION_HTTP_PORT] = {"--http-port", "network", "http_port", CV_PORT, set_http_port},
    [OPTION_HTTP_BIND] = {"--http-bind", "network", "http_bind", CV_ADDR, set_http_bind},
    [OPTION_HTTP_ALLOW_HOST] = {"--http-allow-host", "network", "http_allow_host", CV_HOSTS,
                                set_http_allow_host},
    [OPTION_HTTP_REQUEST_TIMEOUT] = {"--http-request-timeout", "network", "http_request_timeout",
                                     CV_SECONDS, set_http_request_timeout},
    [OPTION_SCRIPT] = {"--script", "script", "startup", CV_PATH, set_script},
    [OPTION_SCRIPT_DIR] = {"--script-dir", "script", "dir", CV_PATH, set_script_dir},
    [OPTION_SCRIPT_AUTOSTART] = {"--no-script-autostart", "script", "autostart", CV_BOOL,
                                 set_script_autostart},
    [OPTION_TIMING] = {"--timing", "timing", "profile", CV_PATH, set_timing},
    [OPTION_SEED] = {"--seed", "timing", "seed", CV_SERIAL, set_seed},
    [OPTION_PHYSICS] = {"--physics", "physics", "engine", CV_PHYSICS, set_physics},
    [OPTION_SCENE] = {"--scene", "physics", "scene", CV_PATH, set_scene},
    [OPTION_PLANT_TIMEOUT] = {"--plant-timeout", "physics", "plant_timeout_ms", CV_MILLISECONDS,
                              set_plant_timeout},
    [OPTION_NET] = {"--net", "net", "conditions", CV_NET, set_net},
};
