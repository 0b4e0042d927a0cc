/* SPDX-License-Identifier: BSD-3-Clause */
/* What a run is configured with (host_options_t): written by the command
 * line (options.c) over the configuration files (config_file.c), both
 * through option_table.h, and read by every layer above. */
#ifndef HOST_HOST_OPTIONS_H
#define HOST_HOST_OPTIONS_H

#include <stdbool.h>
#include <string.h>

#include "hal_log.h"
#include "wsg/wsg_config.h"
#include "net_allow.h"
#include "wire_spec.h"

/* --protocol: what a TCP connection speaks (docs/binary-protocol.md) */
typedef enum { HOST_PROTOCOL_AUTO, HOST_PROTOCOL_GCL, HOST_PROTOCOL_BINARY } host_protocol_t;

/* --physics: the world behind the device's HAL (docs/physics.md) */
typedef enum { HOST_PHYSICS_BUILTIN, HOST_PHYSICS_MUJOCO, HOST_PHYSICS_SOCKET } host_physics_t;
/* --physics socket:PATH: the plant process's Unix-domain socket */
#define HOST_PHYSICS_SOCKET_PREFIX "socket:"
/* --plant-timeout: the default wait for a plant's reply (docs/physics.md
 * "Errors and timeouts") and the longest one may set (an hour) */
#define HOST_PLANT_TIMEOUT_MS_DEFAULT 500u
#define HOST_MILLISECONDS_MAX 3600000

/* --http-allow-host: at most this many lists of names (each repeat one). */
#define HOST_HTTP_ALLOW_LISTS_MAX 16

/* The --config and --save-file read (config_file.h). */
typedef struct config_file config_file_t;

/* --devices: at most this many grippers in one process. */
#define HOST_DEVICES_MAX 10000

typedef struct {
    int tcp_port;
    int udp_port;
    bool udp_port_given; /* --udp-port or udp_port set: else it follows tcp_port */
    bool tcp_enabled;
    bool udp_enabled;
    const char *bind_addr;
    const char *model;
    bool part_given;
    float part_width_mm;
    float part_stiffness_n_mm;
    int max_clients;
    int devices;             /* --devices: grippers served, device i on port + i */
    bool address_per_device; /* --address-per-device: device i on the --bind address + i */
    int idle_timeout_s;      /* --idle-timeout: close TCP connections silent this long; 0: off */
    int udp_peer_timeout_s;  /* --udp-peer-timeout: forget UDP peers silent this long */
    net_allow_t udp_stream_allow; /* --udp-stream-allow: streams to them need no budget */
    bool udp_stream_allow_given;  /* the first --udp-stream-allow replaces the file's list */
    bool disconnect_faststop;
    /* --net and [net] conditions: the wire conditions of every session
     * (docs/network.md); off unless given */
    wire_spec_t net;
    bool trace;
    const char *can_iface; /* --can: finger bus on SocketCAN; NULL: loopback bus */
    const char *fingers;   /* --fingers: the loopback bus' fingers, "fmf,dsa" */
    /* simulation control (docs/simctl.md) */
    int sim_port;              /* --sim-port: control channel; -1: none */
    const char *sim_bind;      /* --sim-bind: NULL: 127.0.0.1 */
    const char *config_path;   /* --config: INI device configuration */
    const char *save_path;     /* --save-file: the web page's Save writes here, read over
                                  --config at start; NULL: Save writes the --config file */
    config_file_t *config;     /* what those two files hold (made by options_parse(), freed
                                  by options_release()); NULL: neither was given */
    const char *scenario_path; /* --scenario: timed control commands */
    const char *record_path;   /* --record: traffic record */
    const char *coverage_path; /* --coverage: report written at exit */
    bool strict;               /* --strict: report tolerated input */
    bool start_paused;         /* --start-paused: simulated clock paused at 0 */
    /* the device's pace (docs/timing.md) */
    const char *timing;          /* --timing: "ideal", a shipped name or an INI path */
    uint32_t seed;               /* --seed: every random choice of the run (run_seed.h) */
    wsg_timing_t timing_figures; /* what --timing names, read once the options are */
    /* the binary protocol (docs/binary-protocol.md) */
    host_protocol_t protocol;
    int binary_udp_port;        /* 0: off */
    bool binary_udp_port_given; /* set explicitly: failing to bind it is fatal */
    int binary_udp_reply_port;  /* 0: the sender's own port */
    bool binary_crc;            /* checksums of requests checked */
    /* the web interface (docs/web.md) */
    int http_port;         /* --http-port: 0: off */
    bool http_port_given;  /* set explicitly: failing to bind it is fatal */
    const char *http_bind; /* --http-bind: NULL: as --bind */
    /* --http-allow-host (and [network] http_allow_host first): the names,
     * comma-separated lists, besides addresses and localhost (http_host.h) */
    const char *http_allow_hosts[HOST_HTTP_ALLOW_LISTS_MAX];
    int http_allow_host_count;
    int http_request_timeout_s; /* --http-request-timeout: a whole request within S */
    /* logging and supervision */
    hal_log_level_t log_level; /* --log-level, --quiet */
    bool log_timestamps;       /* --log-timestamps: wall-clock ISO 8601 on each line */
    const char *log_file;      /* --log-file: NULL: stderr */
    const char *ready_file;    /* --ready-file: written once serving */
    const char *can_log;       /* --can-log: candump -L file of the in-process bus */
    /* user scripts (docs/scripting.md) */
    const char *script;     /* --script: the startup script, a host path or /user/NAME */
    const char *script_dir; /* --script-dir: the /user/ store; NULL: none */
    bool script_autostart;  /* false: --no-script-autostart */
    /* the physics scene (docs/physics.md) */
    host_physics_t physics;    /* --physics: the world behind the HAL */
    const char *scene;         /* --scene: the user's MuJoCo scene; NULL: the default scene */
    const char *plant_socket;  /* --physics socket:PATH: PATH */
    unsigned plant_timeout_ms; /* --plant-timeout: how long the device waits for a reply */
    /* --list-models [--json]: printed once every option is read */
    bool list_models;
    bool list_models_json;
} host_options_t;

/* "builtin", "mujoco" or "socket:PATH" (the option and the configuration
 * key). */
static inline bool options_parse_physics(const char *text, host_physics_t *out)
{
    size_t prefix = strlen(HOST_PHYSICS_SOCKET_PREFIX);
    if (strncmp(text, HOST_PHYSICS_SOCKET_PREFIX, prefix) == 0 && text[prefix] != '\0') {
        *out = HOST_PHYSICS_SOCKET;
        return true;
    }
    if (strcmp(text, "builtin") == 0 || strcmp(text, "mujoco") == 0) {
        *out = text[0] == 'b' ? HOST_PHYSICS_BUILTIN : HOST_PHYSICS_MUJOCO;
        return true;
    }
    return false;
}

/* "auto", "gcl" or "binary" (the option and the configuration key). */
static inline bool options_parse_protocol(const char *text, host_protocol_t *out)
{
    static const char *const names[] = {"auto", "gcl", "binary"};
    for (unsigned i = 0; i < 3; i++) {
        if (strcmp(text, names[i]) == 0) {
            *out = (host_protocol_t)i;
            return true;
        }
    }
    return false;
}

#endif
