/* SPDX-License-Identifier: BSD-3-Clause */
/* --help and --list-models: what options_parse() prints. */
#include <cjson/cJSON.h>
#include <stdio.h>

#include "config_file.h"
#include "options_internal.h"
#include "sim/sim_models.h"

/* What is served, where, and the world at start. */
static void print_serving(void)
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
           "  --physics ENGINE           the world behind the device: builtin (default) or\n"
           "                             mujoco, a physics scene (docs/physics.md), or\n"
           "                             socket:PATH, a plant process (another engine)\n"
           "                             listening at the Unix socket PATH\n"
           "  --scene FILE.xml           with --physics mujoco: the scene (MJCF) the\n"
           "                             gripper works in (default: a box on a table)\n"
           "  --plant-timeout MS         with --physics socket:PATH: a plant that does not\n"
           "                             answer within MS wall-clock ms (1 to 3600000,\n"
           "                             default 500) is lost: a power fault\n"
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
           "  --net SPEC                 wire conditions for every session: a preset (off,\n"
           "                             rough, split, lossy, slow) and/or KEY=VALUE items:\n"
           "                             split=N, gap=MS[-MS], coalesce=MS, latency=MS,\n"
           "                             jitter=MS, reset=MS, loss=P, dup=P, reorder=P,\n"
           "                             seed=N (e.g. --net rough,reset=5000; default off;\n"
           "                             docs/network.md)\n",
           DEFAULT_PORT, DEFAULT_PORT, HOST_DEVICES_MAX, wsg_sim_model_default()->name,
           (double)DEFAULT_PART_STIFFNESS, DEFAULT_MAX_CLIENTS, MAX_CLIENTS_LIMIT,
           DEFAULT_UDP_PEER_TIMEOUT_S);
}

/* The finger bus, the configuration files and the simulation control. */
static void print_simulation(void)
{
    printf("  --trace                    log every line in and out on stderr\n"
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
           "  --timing PROFILE           the device's pace (docs/timing.md): ideal (default:\n"
           "                             every request answered at once), wsg50 (the real\n"
           "                             device's, from public figures) or an INI file\n"
           "  --seed N                   seeds every random choice of the run (timing\n"
           "                             jitter, wire conditions); 0-4294967295, default 1\n"
           "  --record FILE              record every line in and out with timestamps, and\n"
           "                             the device's state while it moves (tools/wsgplot)\n"
           "  --coverage FILE            write a protocol coverage report at exit, with the\n"
           "                             report on the driver under test (also logged)\n"
           "  --strict                   report input the manual does not allow but the\n"
           "                             emulator tolerates (coverage report and trace)\n");
}

/* The binary protocol and the web interface. */
static void print_protocols(void)
{
    printf("  --protocol P               what TCP connections speak: auto (default: a first\n"
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
           "                             after it opened or its last reply (default %d)\n",
           DEFAULT_HTTP_PORT, DEFAULT_HTTP_REQUEST_TIMEOUT_S);
}

/* Logging, supervision, scripts and the help itself. */
static void print_service(void)
{
    printf("  --log-level LEVEL          log error, warn, info or debug messages and above\n"
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
           "  -h, --help                 print this help and exit\n");
}

void options_print_help(void)
{
    print_serving();
    print_simulation();
    print_protocols();
    print_service();
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

void options_list_models(bool json)
{
    if (json) {
        list_models_json();
    } else {
        list_models_text();
    }
}
