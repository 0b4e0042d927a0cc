/* SPDX-License-Identifier: BSD-3-Clause */
#include "config_file.h"

#include <arpa/inet.h>
#include <errno.h>
#include <ini.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>

#include "settings_table.h"
#include "sim/finger_node.h"
#include "sim/sim_models.h"
#include "text_file.h"
#include "web/web_host.h"

#define TEXT_MAX WSG_CONFIG_STRING_MAX
#define MAX_CLIENTS_LIMIT 128
#define FILE_LINE_MAX 4096        /* a comment line may be this long */
#define FILE_BYTES_MAX (1u << 20) /* a device configuration is a few KiB */

typedef enum {
    K_TEXT,        /* printable, no '"', shorter than WSG_CONFIG_STRING_MAX */
    K_MODEL,       /* a model wsg_sim_model_find() knows */
    K_SERIAL,      /* 0..4294967295 */
    K_NUMBER,      /* a finite number; ranges are checked against the model */
    K_BOOL,        /* yes/no, true/false, on/off, 1/0 */
    K_DIRECTION,   /* positive/negative */
    K_PORT,        /* 0..65535 */
    K_PORT_OFF,    /* 0..65535 or "off" (-1) */
    K_CLIENTS,     /* 1..128 */
    K_SECONDS,     /* 1..86400 */
    K_SECONDS_OFF, /* 0..86400 or "off" (0) */
    K_ADDR,        /* an IPv4 or IPv6 address */
    K_LOOPBACK,    /* a loopback address only */
    K_PROTOCOL,    /* auto, gcl or binary */
    K_HOSTS,       /* host names, comma-separated (web_host_names_valid) */
    K_PATH,        /* a file or directory name: printable, not empty */
    K_ALLOW,       /* comma-separated ADDR[/PREFIX] (net_allow.h) */
    K_FINGERS,     /* A[,B]: the fingers of a loopback bus (wsg_finger_node_parse_pair) */
} kind_t;

typedef enum {
    DEV_MODEL,
    DEV_SERIAL,
    DEV_TAG,
    DEV_VERSION,
    MOT_HOMING,
    MOT_MOVE_RETARGET,
    NET_TCP_PORT,
    NET_UDP_PORT,
    NET_BIND,
    NET_MAX_CLIENTS,
    NET_ADDRESS_PER_DEVICE,
    NET_IDLE_TIMEOUT,
    NET_UDP_PEER_TIMEOUT,
    NET_SIM_PORT,
    NET_SIM_BIND,
    NET_PROTOCOL,
    NET_BINARY_UDP_PORT,
    NET_BINARY_UDP_REPLY_PORT,
    NET_HTTP_PORT,
    NET_HTTP_BIND,
    NET_HTTP_ALLOW_HOST,
    NET_HTTP_REQUEST_TIMEOUT,
    SCRIPT_STARTUP,
    SCRIPT_DIR,
    SCRIPT_AUTOSTART,
    NET_UDP_STREAM_ALLOW,
    KEY_COUNT
} key_id_t;

/* The keys besides the device settings of settings_table.h, which the file
 * reads from that table. */
static const struct {
    const char *section;
    const char *name;
    kind_t kind;
} keys[KEY_COUNT] = {
    [DEV_MODEL] = {"device", "model", K_MODEL},
    [DEV_SERIAL] = {"device", "serial", K_SERIAL},
    [DEV_TAG] = {"device", "tag", K_TEXT},
    [DEV_VERSION] = {"device", "firmware_version", K_TEXT},
    [MOT_HOMING] = {"motion", "homing_direction", K_DIRECTION},
    [MOT_MOVE_RETARGET] = {"motion", "move_retarget", K_BOOL},
    [NET_TCP_PORT] = {"network", "tcp_port", K_PORT},
    [NET_UDP_PORT] = {"network", "udp_port", K_PORT},
    [NET_BIND] = {"network", "bind", K_ADDR},
    [NET_MAX_CLIENTS] = {"network", "max_clients", K_CLIENTS},
    [NET_ADDRESS_PER_DEVICE] = {"network", "address_per_device", K_BOOL},
    [NET_IDLE_TIMEOUT] = {"network", "idle_timeout", K_SECONDS_OFF},
    [NET_UDP_PEER_TIMEOUT] = {"network", "udp_peer_timeout", K_SECONDS},
    [NET_SIM_PORT] = {"network", "sim_port", K_PORT_OFF},
    [NET_SIM_BIND] = {"network", "sim_bind", K_LOOPBACK},
    [NET_PROTOCOL] = {"network", "protocol", K_PROTOCOL},
    [NET_BINARY_UDP_PORT] = {"network", "binary_udp_port", K_PORT},
    [NET_BINARY_UDP_REPLY_PORT] = {"network", "binary_udp_reply_port", K_PORT},
    [NET_HTTP_PORT] = {"network", "http_port", K_PORT},
    [NET_HTTP_BIND] = {"network", "http_bind", K_ADDR},
    [NET_HTTP_ALLOW_HOST] = {"network", "http_allow_host", K_HOSTS},
    [NET_HTTP_REQUEST_TIMEOUT] = {"network", "http_request_timeout", K_SECONDS},
    [SCRIPT_STARTUP] = {"script", "startup", K_PATH},
    [SCRIPT_DIR] = {"script", "dir", K_PATH},
    [SCRIPT_AUTOSTART] = {"script", "autostart", K_BOOL},
    [NET_UDP_STREAM_ALLOW] = {"network", "udp_stream_allow", K_ALLOW},
};

typedef struct {
    bool set;
    const char *file; /* where it was set: one of config_file_t's files */
    int line;
    double number;
    char text[128]; /* as written (texts are checked against TEXT_MAX) */
} value_t;

/* [device.N]: one device of a fleet declared on its own; its keys override
 * the global ones for that device (docs/simctl.md, "Device configuration"). */
typedef enum {
    SEC_MODEL,
    SEC_SERIAL,
    SEC_TAG,
    SEC_TCP_PORT,
    SEC_UDP_PORT,
    SEC_SCRIPT,
    SEC_FINGERS,
    SEC_KEY_COUNT
} sec_key_t;

static const struct {
    const char *name;
    kind_t kind;
} sec_keys[SEC_KEY_COUNT] = {
    [SEC_MODEL] = {"model", K_MODEL},
    [SEC_SERIAL] = {"serial", K_SERIAL},
    [SEC_TAG] = {"tag", K_TEXT},
    [SEC_TCP_PORT] = {"tcp_port", K_PORT},
    [SEC_UDP_PORT] = {"udp_port", K_PORT},
    [SEC_SCRIPT] = {"script", K_PATH},
    [SEC_FINGERS] = {"fingers", K_FINGERS},
};

#define DEVICE_SECTION "device."

typedef struct {
    unsigned index;
    value_t values[SEC_KEY_COUNT];
} device_section_t;

/* The files read: --config, then the --save-file overlay, whose lines count
 * as if they followed the --config file's. */
#define FILES_MAX 2

struct config_file {
    char files[FILES_MAX][256];
    unsigned file_count;
    const char *saved; /* the --save-file among files, NULL: none read */
    value_t values[KEY_COUNT];
    value_t settings[SETTINGS_TABLE_COUNT]; /* by the rows of settings_table */
    device_section_t *sections;             /* malloc'd, in the order of the file */
    unsigned section_count;
    const char *model; /* the devices' model without a [device.N] one (config_file_check) */
};

/* What the parser is doing: the reader counts lines for the handler. */
typedef struct {
    text_file_t file;
    config_file_t *cf; /* what it reads into */
    const char *path;  /* one of cf->files */
    int line;
    bool failed;
} parse_state_t;

static bool fail_at(const char *path, int line, const char *section, const char *name,
                    const char *why)
{
    fprintf(stderr, "wsgsim: %s:%d: [%s] %s: %s\n", path, line, section, name, why);
    return false;
}

/* Remembers where a value was set. */
static void mark_set(value_t *v, const parse_state_t *st)
{
    v->set = true;
    v->file = st->path;
    v->line = st->line;
}

static bool parse_number(const char *text, double *out)
{
    char *end = NULL;
    errno = 0;
    double v = strtod(text, &end);
    if (end == text || *end != '\0' || errno != 0 || !isfinite(v)) {
        return false;
    }
    *out = v;
    return true;
}

static bool parse_bool(const char *text, double *out)
{
    static const char *const yes[] = {"yes", "true", "on", "1"};
    static const char *const no[] = {"no", "false", "off", "0"};
    for (unsigned i = 0; i < 4; i++) {
        if (strcasecmp(text, yes[i]) == 0 || strcasecmp(text, no[i]) == 0) {
            *out = strcasecmp(text, yes[i]) == 0 ? 1.0 : 0.0;
            return true;
        }
    }
    return false;
}

static bool parse_int_range(const char *text, double min, double max, double *out)
{
    return parse_number(text, out) && *out == floor(*out) && *out >= min && *out <= max;
}

static bool is_loopback(const char *addr)
{
    struct in_addr v4;
    struct in6_addr v6;
    if (inet_pton(AF_INET, addr, &v4) == 1) {
        return (ntohl(v4.s_addr) >> 24) == 127u;
    }
    return inet_pton(AF_INET6, addr, &v6) == 1 && IN6_IS_ADDR_LOOPBACK(&v6);
}

static bool is_address(const char *addr)
{
    unsigned char buf[sizeof(struct in6_addr)];
    return inet_pton(AF_INET, addr, buf) == 1 || inet_pton(AF_INET6, addr, buf) == 1;
}

static bool text_ok_long(const char *text)
{
    for (const char *p = text; *p != '\0'; p++) {
        if (*p < 0x20 || *p > 0x7e) {
            return false;
        }
    }
    return true;
}

/* The device's own rule for its texts (wsg_config_text_char_ok). */
static bool text_ok(const char *text)
{
    for (const char *p = text; *p != '\0'; p++) {
        if (!wsg_config_text_char_ok(*p)) {
            return false;
        }
    }
    return strlen(text) < TEXT_MAX;
}

/* Converts one value by its kind; NULL when fine, else why not. */
static const char *convert(kind_t kind, const char *text, value_t *v)
{
    snprintf(v->text, sizeof(v->text), "%s", text);
    switch (kind) {
    case K_TEXT:
        return text_ok(text) ? NULL : "expected printable text without '\"', at most 47 characters";
    case K_MODEL:
        return wsg_sim_model_find(text) != NULL ? NULL : "unknown model (see wsgsim --list-models)";
    case K_SERIAL:
        return parse_int_range(text, 0, 4294967295.0, &v->number)
                   ? NULL
                   : "expected an integer 0-4294967295";
    case K_NUMBER:
        return parse_number(text, &v->number) ? NULL : "expected a number";
    case K_BOOL:
        return parse_bool(text, &v->number) ? NULL : "expected yes/no, true/false, on/off or 1/0";
    case K_DIRECTION:
        v->number = strcasecmp(text, "positive") == 0 ? 1.0 : 0.0;
        return strcasecmp(text, "positive") == 0 || strcasecmp(text, "negative") == 0
                   ? NULL
                   : "expected positive or negative";
    case K_PORT:
        return parse_int_range(text, 0, 65535, &v->number) ? NULL : "expected a port 0-65535";
    case K_PORT_OFF:
        v->number = -1.0;
        return strcasecmp(text, "off") == 0 || parse_int_range(text, 0, 65535, &v->number)
                   ? NULL
                   : "expected a port 0-65535 or off";
    case K_CLIENTS:
        return parse_int_range(text, 1, MAX_CLIENTS_LIMIT, &v->number) ? NULL : "expected 1-128";
    case K_SECONDS:
        return parse_int_range(text, 1, 86400, &v->number) ? NULL : "expected seconds 1-86400";
    case K_SECONDS_OFF:
        v->number = 0.0;
        return strcasecmp(text, "off") == 0 || parse_int_range(text, 0, 86400, &v->number)
                   ? NULL
                   : "expected seconds 0-86400 or off";
    case K_ADDR:
        return is_address(text) ? NULL : "expected an IPv4 or IPv6 address";
    case K_PROTOCOL: {
        host_protocol_t protocol = HOST_PROTOCOL_AUTO;
        bool ok = options_parse_protocol(text, &protocol);
        v->number = (double)protocol;
        return ok ? NULL : "expected auto, gcl or binary";
    }
    case K_HOSTS:
        return strlen(text) < sizeof(v->text) && web_host_names_valid(text)
                   ? NULL
                   : "expected host names separated by commas (or *), at most 127 characters";
    case K_PATH:
        return text[0] != '\0' && strlen(text) < sizeof(v->text) - 1u && text_ok_long(text)
                   ? NULL
                   : "expected a path of printable characters";
    case K_FINGERS: {
        fbus_type_t types[FBUS_SLOTS];
        return wsg_finger_node_parse_pair(text, types)
                   ? NULL
                   : "expected fingers A[,B], each none, generic, fmf or dsa";
    }
    case K_ALLOW: {
        net_allow_t list = {.count = 0};
        return strlen(text) < sizeof(v->text) && net_allow_add(&list, text)
                   ? NULL
                   : "expected up to 8 comma-separated addresses, each ADDR or ADDR/PREFIX";
    }
    case K_LOOPBACK:
        return is_loopback(text) ? NULL
                                 : "the control port may only be bound to a loopback address "
                                   "here; use --sim-bind on the command line to expose it";
    default:
        return "unsupported";
    }
}

/* Surrounding double quotes are optional in the file. */
static void unquote(const char *value, char *out, size_t cap)
{
    size_t len = strlen(value);
    if (len >= 2 && value[0] == '"' && value[len - 1] == '"') {
        snprintf(out, cap, "%.*s", (int)(len - 2), value + 1);
    } else {
        snprintf(out, cap, "%s", value);
    }
}

/* The section of device index, added when new; NULL when out of memory. */
static device_section_t *section_of(config_file_t *cf, unsigned index)
{
    for (unsigned i = 0; i < cf->section_count; i++) {
        if (cf->sections[i].index == index) {
            return &cf->sections[i];
        }
    }
    device_section_t *grown =
        realloc(cf->sections, (cf->section_count + 1u) * sizeof(*cf->sections));
    if (grown == NULL) {
        return NULL;
    }
    cf->sections = grown;
    device_section_t *d = &cf->sections[cf->section_count++];
    memset(d, 0, sizeof(*d));
    d->index = index;
    return d;
}

/* N of "[device.N]", 0..HOST_DEVICES_MAX-1; false for anything else. */
static bool section_index(const char *section, unsigned *index)
{
    const char *digits = section + strlen(DEVICE_SECTION);
    double n = 0.0;
    bool plain = digits[0] != '\0' && strspn(digits, "0123456789") == strlen(digits);
    if (!plain || !parse_int_range(digits, 0, HOST_DEVICES_MAX - 1, &n)) {
        return false;
    }
    *index = (unsigned)n;
    return true;
}

static int on_device_key(parse_state_t *st, const char *section, const char *name, const char *text)
{
    unsigned index = 0;
    if (!section_index(section, &index)) {
        char why[64];
        snprintf(why, sizeof(why), "a device section is [device.N], N 0-%d", HOST_DEVICES_MAX - 1);
        st->failed = true;
        return fail_at(st->path, st->line, section, name, why);
    }
    device_section_t *d = section_of(st->cf, index);
    for (unsigned k = 0; k < SEC_KEY_COUNT && d != NULL; k++) {
        if (strcasecmp(sec_keys[k].name, name) != 0) {
            continue;
        }
        const char *why = convert(sec_keys[k].kind, text, &d->values[k]);
        if (why != NULL) {
            st->failed = true;
            return fail_at(st->path, st->line, section, name, why);
        }
        mark_set(&d->values[k], st);
        return 1;
    }
    st->failed = true;
    return fail_at(st->path, st->line, section, name,
                   d == NULL ? "out of memory"
                             : "unknown key in a device section (model, serial, tag, tcp_port, "
                               "udp_port, script, fingers)");
}

/* A device setting of settings_table.h, else an unknown key. */
static int on_setting_key(parse_state_t *st, const char *section, const char *name,
                          const char *text)
{
    for (unsigned i = 0; i < SETTINGS_TABLE_COUNT; i++) {
        const settings_row_t *row = &settings_table[i];
        if (row->ini_key == NULL || strcasecmp(row->ini_section, section) != 0 ||
            strcasecmp(row->ini_key, name) != 0) {
            continue;
        }
        kind_t kind = settings_table_is_switch(row) ? K_BOOL : K_NUMBER;
        const char *why = convert(kind, text, &st->cf->settings[i]);
        if (why != NULL) {
            st->failed = true;
            return fail_at(st->path, st->line, section, name, why);
        }
        mark_set(&st->cf->settings[i], st);
        return 1;
    }
    st->failed = true;
    return fail_at(st->path, st->line, section, name, "unknown key (see docs/wsgsim.example.ini)");
}

/* The file's value of a device setting (set false: none). */
static const value_t *setting_value(const config_file_t *cf, wsg_setting_t id)
{
    return &cf->settings[settings_table_row(id) - settings_table];
}

/* The value as the file holds it, surrounding double quotes optional. A
 * quoted value is read whole: libinih ends a value at " ;" (its inline
 * comment), so a tag "a ;b", which the device takes and the Save writes,
 * came back as "a and stopped the next start. Its closing quote is the
 * next one on the line (a text value holds none). */
static void value_text(const parse_state_t *st, const char *value, char *out, size_t cap)
{
    const char *open = strchr(st->file.line, '"');
    const char *close = open != NULL ? strchr(open + 1, '"') : NULL;
    const char *after = close != NULL ? close + 1 + strspn(close + 1, " \t") : NULL;
    size_t len = strlen(value);
    bool cut = len >= 1 && value[0] == '"' && (len == 1 || value[len - 1] != '"');
    if (cut && after != NULL && (*after == '\0' || *after == ';')) { /* a comment may follow */
        snprintf(out, cap, "%.*s", (int)(close - open - 1), open + 1);
    } else {
        unquote(value, out, cap);
    }
}

static int on_key(void *user, const char *section, const char *name, const char *value)
{
    parse_state_t *st = user;
    char text[128];
    value_text(st, value, text, sizeof(text));
    if (strncasecmp(section, DEVICE_SECTION, strlen(DEVICE_SECTION)) == 0) {
        return on_device_key(st, section, name, text);
    }
    for (unsigned i = 0; i < KEY_COUNT; i++) {
        if (strcasecmp(keys[i].section, section) != 0 || strcasecmp(keys[i].name, name) != 0) {
            continue;
        }
        const char *why = convert(keys[i].kind, text, &st->cf->values[i]);
        if (why != NULL) {
            st->failed = true;
            return fail_at(st->path, st->line, section, name, why);
        }
        mark_set(&st->cf->values[i], st);
        return 1;
    }
    return on_setting_key(st, section, name, text);
}

static bool is_comment(const char *text)
{
    const char *p = text + strspn(text, " \t");
    return *p == ';' || *p == '#';
}

/* The first CR, vertical tab or form feed in text, or NULL. libinih takes
 * them for blanks where the Save does not: in a section or key line they
 * would make the two read a file differently. (Other control characters
 * are the values' and keys' own checks to refuse.) */
static const char *odd_blank(const char *text)
{
    size_t at = strcspn(text, "\r\v\f");
    return text[at] != '\0' ? text + at : NULL;
}

/* libinih's reader: hands it one whole line per call, without indentation.
 * A comment line of any length becomes an empty line; any other line must
 * hold no CR, vertical tab or form feed and fit libinih's line buffer (num
 * bytes with "\n" and NUL), else it is refused, never split. */
static char *read_line(char *str, int num, void *stream)
{
    parse_state_t *st = stream;
    text_file_read_t got = st->failed ? TEXT_FILE_END : text_file_next(&st->file);
    st->failed = st->failed || got == TEXT_FILE_ERROR;
    if (got != TEXT_FILE_LINE) {
        return NULL;
    }
    st->line = st->file.number;
    /* without its indentation: libinih would take an indented line for the
     * continuation of the key before it, which this file format has not */
    const char *text =
        is_comment(st->file.line) ? "" : st->file.line + strspn(st->file.line, " \t");
    const char *bad = odd_blank(text);
    if (bad != NULL) {
        st->failed = true;
        text_file_fail(&st->file,
                       "control character 0x%02x at column %zu (a section or key line holds no "
                       "CR, vertical tab or form feed)",
                       (unsigned)(unsigned char)*bad, (size_t)(bad - st->file.line) + 1u);
        return NULL;
    }
    size_t len = strlen(text);
    if (num < 2 || len > (size_t)num - 2) {
        st->failed = true;
        text_file_fail(&st->file,
                       "line too long for a section or key line (at most %d characters; a "
                       "comment goes on a line of its own)",
                       num - 2);
        return NULL;
    }
    memcpy(str, text, len);
    str[len] = '\n';
    str[len + 1] = '\0';
    return str;
}

static void apply_binary(const config_file_t *cf, host_options_t *opts)
{
    const value_t *v = cf->values;
    if (v[NET_PROTOCOL].set) {
        opts->protocol = (host_protocol_t)v[NET_PROTOCOL].number;
    }
    if (v[NET_BINARY_UDP_PORT].set) {
        opts->binary_udp_port = (int)v[NET_BINARY_UDP_PORT].number;
        opts->binary_udp_port_given = true;
    }
    if (v[NET_BINARY_UDP_REPLY_PORT].set) {
        opts->binary_udp_reply_port = (int)v[NET_BINARY_UDP_REPLY_PORT].number;
    }
    const value_t *crc = setting_value(cf, WSG_SET_BINARY_CRC_CHECK);
    if (crc->set) { /* reaches the device through the options */
        opts->binary_crc = crc->number != 0.0;
    }
    if (v[NET_HTTP_PORT].set) {
        opts->http_port = (int)v[NET_HTTP_PORT].number;
        opts->http_port_given = true;
    }
    if (v[NET_HTTP_BIND].set) {
        opts->http_bind = v[NET_HTTP_BIND].text;
    }
    if (v[NET_HTTP_ALLOW_HOST].set) { /* the first list: the command line adds its own */
        opts->http_allow_hosts[opts->http_allow_host_count++] = v[NET_HTTP_ALLOW_HOST].text;
    }
    if (v[NET_HTTP_REQUEST_TIMEOUT].set) {
        opts->http_request_timeout_s = (int)v[NET_HTTP_REQUEST_TIMEOUT].number;
    }
}

/* [script]: the startup script and the store (docs/scripting.md). */
static void apply_script(const config_file_t *cf, host_options_t *opts)
{
    const value_t *v = cf->values;
    if (v[SCRIPT_STARTUP].set) {
        opts->script = v[SCRIPT_STARTUP].text;
    }
    if (v[SCRIPT_DIR].set) {
        opts->script_dir = v[SCRIPT_DIR].text;
    }
    if (v[SCRIPT_AUTOSTART].set) {
        opts->script_autostart = v[SCRIPT_AUTOSTART].number != 0.0;
    }
}

static void apply_host(const config_file_t *cf, host_options_t *opts)
{
    const value_t *v = cf->values;
    if (v[DEV_MODEL].set) {
        opts->model = v[DEV_MODEL].text;
    }
    if (v[NET_TCP_PORT].set) {
        opts->tcp_port = (int)v[NET_TCP_PORT].number;
    }
    if (v[NET_UDP_PORT].set) {
        opts->udp_port = (int)v[NET_UDP_PORT].number;
        opts->udp_port_given = true;
    }
    if (v[NET_BIND].set) {
        opts->bind_addr = v[NET_BIND].text;
    }
    if (v[NET_MAX_CLIENTS].set) {
        opts->max_clients = (int)v[NET_MAX_CLIENTS].number;
    }
    const value_t *faststop = setting_value(cf, WSG_SET_DISCONNECT_FASTSTOP);
    if (faststop->set) { /* reaches the device through the options */
        opts->disconnect_faststop = faststop->number != 0.0;
    }
    if (v[NET_ADDRESS_PER_DEVICE].set) {
        opts->address_per_device = v[NET_ADDRESS_PER_DEVICE].number != 0.0;
    }
    if (v[NET_IDLE_TIMEOUT].set) {
        opts->idle_timeout_s = (int)v[NET_IDLE_TIMEOUT].number;
    }
    if (v[NET_UDP_PEER_TIMEOUT].set) {
        opts->udp_peer_timeout_s = (int)v[NET_UDP_PEER_TIMEOUT].number;
    }
    if (v[NET_SIM_PORT].set) {
        opts->sim_port = (int)v[NET_SIM_PORT].number;
    }
    if (v[NET_SIM_BIND].set) {
        opts->sim_bind = v[NET_SIM_BIND].text;
    }
    if (v[NET_UDP_STREAM_ALLOW].set) {
        opts->udp_stream_allow.count = 0;
        (void)net_allow_add(&opts->udp_stream_allow, v[NET_UDP_STREAM_ALLOW].text); /* checked */
    }
    apply_binary(cf, opts);
    apply_script(cf, opts);
}

static void config_file_forget(config_file_t *cf)
{
    free(cf->sections);
    memset(cf, 0, sizeof(*cf));
}

/* Reads one file over what was read before; option names it in messages. */
static bool parse_file(config_file_t *cf, const char *path, const char *option)
{
    char *name = cf->files[cf->file_count++];
    snprintf(name, sizeof(cf->files[0]), "%s", path);
    parse_state_t st = {.cf = cf, .path = name, .line = 0, .failed = false};
    if (!text_file_open(&st.file, path, option, FILE_LINE_MAX, FILE_BYTES_MAX)) {
        return false;
    }
    int result = ini_parse_stream(read_line, &st, on_key, &st);
    text_file_close(&st.file);
    if (result > 0 && !st.failed) {
        fprintf(stderr, "wsgsim: %s:%d: not a section header or key = value line\n", path, result);
    }
    return result == 0 && !st.failed;
}

/* A save file that does not exist yet: nothing was saved. */
static bool nothing_saved(const char *path)
{
    struct stat st;
    return stat(path, &st) != 0 && errno == ENOENT;
}

config_file_t *config_file_create(void)
{
    return calloc(1, sizeof(config_file_t));
}

void config_file_destroy(config_file_t *cf)
{
    if (cf != NULL) {
        free(cf->sections);
        free(cf);
    }
}

bool config_file_load(config_file_t *cf, const char *config_path, const char *save_path,
                      host_options_t *opts)
{
    config_file_forget(cf);
    if (config_path != NULL && !parse_file(cf, config_path, "--config")) {
        return false;
    }
    if (save_path != NULL && !nothing_saved(save_path)) {
        if (!parse_file(cf, save_path, "--save-file")) {
            return false;
        }
        cf->saved = cf->files[cf->file_count - 1u];
    }
    apply_host(cf, opts);
    return true;
}

static bool check_range(const config_file_t *cf, const settings_row_t *row, double min, double max)
{
    const value_t *v = setting_value(cf, row->id);
    if (!v->set || (v->number >= min && v->number <= max)) {
        return true;
    }
    char why[96]; /* a number written with 50 characters or more is cut short */
    int len = snprintf(why, sizeof(why), "%s is outside %g..%g for this model", v->text, min, max);
    return len >= 0 && fail_at(v->file, v->line, row->ini_section, row->ini_key, why);
}

static bool check_soft_limits(const config_file_t *cf, const wsg_config_t *cfg)
{
    float minus = cfg->soft_limit_minus_mm;
    float plus = cfg->soft_limit_plus_mm;
    if (minus < plus) {
        return true;
    }
    wsg_setting_t id =
        setting_value(cf, WSG_SET_SOFT_PLUS)->set ? WSG_SET_SOFT_PLUS : WSG_SET_SOFT_MINUS;
    return fail_at(setting_value(cf, id)->file, setting_value(cf, id)->line, "motion",
                   settings_table_row(id)->ini_key,
                   "soft_limit_minus must be below soft_limit_plus");
}

/* The [motion] keys whose range depends on the model: the numbers. */
static bool is_ranged(const settings_row_t *row)
{
    return row->ini_key != NULL && !settings_table_is_switch(row);
}

static bool check_model(config_file_t *cf, const char *model)
{
    const sim_model_t *m = wsg_sim_model_find(model);
    if (m == NULL) {
        return false;
    }
    for (unsigned i = 0; i < SETTINGS_TABLE_COUNT; i++) {
        double min, max;
        if (!is_ranged(&settings_table[i])) {
            continue;
        }
        settings_table_model_range(&settings_table[i], m, &min, &max);
        if (!check_range(cf, &settings_table[i], min, max)) {
            return false;
        }
    }
    wsg_config_t cfg;
    wsg_sim_model_config(m, &cfg);
    config_file_apply(cf, &cfg);
    return check_soft_limits(cf, &cfg);
}

/* The motion settings are checked against every model a device runs. */
bool config_file_check(config_file_t *cf, const char *model)
{
    cf->model = model;
    bool ok = check_model(cf, model);
    for (unsigned i = 0; i < cf->section_count && ok; i++) {
        const value_t *m = &cf->sections[i].values[SEC_MODEL];
        ok = !m->set || check_model(cf, m->text);
    }
    return ok;
}

static bool motion_fits_model(const wsg_config_t *cfg, const char *model, char *why, size_t cap)
{
    const sim_model_t *m = wsg_sim_model_find(model);
    for (unsigned i = 0; m != NULL && i < SETTINGS_TABLE_COUNT; i++) {
        const settings_row_t *row = &settings_table[i];
        double min, max;
        if (!is_ranged(row)) {
            continue;
        }
        double value = wsg_config_setting_get(cfg, row->id);
        settings_table_model_range(row, m, &min, &max);
        if (!(value >= min && value <= max)) {
            snprintf(why, cap,
                     "%s: %g is outside %g..%g for the %s in the file (the [motion] settings "
                     "are every device's)",
                     row->ini_key, value, min, max, model);
            return false;
        }
    }
    return true;
}

bool config_file_motion_fits(const config_file_t *cf, const wsg_config_t *cfg, char *why,
                             size_t cap)
{
    if (cf == NULL) {
        return true; /* no file: nothing to fit */
    }
    if (cf->model != NULL && !motion_fits_model(cfg, cf->model, why, cap)) {
        return false;
    }
    for (unsigned i = 0; i < cf->section_count; i++) {
        const value_t *m = &cf->sections[i].values[SEC_MODEL];
        if (m->set && !motion_fits_model(cfg, m->text, why, cap)) {
            return false;
        }
    }
    return true;
}

static const device_section_t *find_section(const config_file_t *cf, unsigned index)
{
    if (cf == NULL) {
        return NULL;
    }
    for (unsigned i = 0; i < cf->section_count; i++) {
        if (cf->sections[i].index == index) {
            return &cf->sections[i];
        }
    }
    return NULL;
}

bool config_file_device_sets_tag(const config_file_t *cf, unsigned index)
{
    const device_section_t *d = find_section(cf, index);
    return d != NULL && d->values[SEC_TAG].set;
}

unsigned config_file_devices(const config_file_t *cf)
{
    unsigned count = 0;
    for (unsigned i = 0; cf != NULL && i < cf->section_count; i++) {
        unsigned after = cf->sections[i].index + 1u;
        count = after > count ? after : count;
    }
    return count;
}

const char *config_file_device_model(const config_file_t *cf, unsigned index, const char *fallback)
{
    const device_section_t *d = find_section(cf, index);
    return d != NULL && d->values[SEC_MODEL].set ? d->values[SEC_MODEL].text : fallback;
}

const char *config_file_device_script(const config_file_t *cf, unsigned index, const char *fallback)
{
    const device_section_t *d = find_section(cf, index);
    return d != NULL && d->values[SEC_SCRIPT].set ? d->values[SEC_SCRIPT].text : fallback;
}

bool config_file_startup_saved(const config_file_t *cf, unsigned index, const char *script)
{
    const device_section_t *d = find_section(cf, index);
    const value_t *own = d != NULL ? &d->values[SEC_SCRIPT] : NULL;
    const value_t *from = NULL;
    if (cf == NULL || cf->saved == NULL || script == NULL) {
        return false;
    }
    if (own != NULL && own->set && script == own->text) {
        from = own;
    } else if (cf->values[SCRIPT_STARTUP].set && script == cf->values[SCRIPT_STARTUP].text) {
        from = &cf->values[SCRIPT_STARTUP];
    }
    const value_t *autostart = &cf->values[SCRIPT_AUTOSTART];
    bool saved_off = autostart->set && autostart->file == cf->saved && autostart->number == 0.0;
    /* NULL: the command line's own --script, which the files do not decide */
    return from != NULL && (from->file == cf->saved || saved_off);
}

const char *config_file_device_fingers(const config_file_t *cf, unsigned index,
                                       const char *fallback)
{
    const device_section_t *d = find_section(cf, index);
    return d != NULL && d->values[SEC_FINGERS].set ? d->values[SEC_FINGERS].text : fallback;
}

bool config_file_device_port(const config_file_t *cf, unsigned index, bool udp, int *port)
{
    const device_section_t *d = find_section(cf, index);
    const value_t *v = d != NULL ? &d->values[udp ? SEC_UDP_PORT : SEC_TCP_PORT] : NULL;
    if (v != NULL && udp && !v->set) {
        v = &d->values[SEC_TCP_PORT]; /* the UDP port follows the TCP port */
    }
    if (v == NULL || !v->set) {
        return false;
    }
    *port = (int)v->number;
    return true;
}

void config_file_apply_device(const config_file_t *cf, unsigned index, wsg_config_t *cfg)
{
    const device_section_t *d = find_section(cf, index);
    if (d == NULL) {
        return;
    }
    if (d->values[SEC_SERIAL].set) {
        cfg->serial = (uint32_t)d->values[SEC_SERIAL].number;
    }
    if (d->values[SEC_TAG].set) {
        size_t len = strnlen(d->values[SEC_TAG].text, WSG_CONFIG_STRING_MAX - 1);
        memcpy(cfg->tag, d->values[SEC_TAG].text, len); /* checked shorter on load */
        cfg->tag[len] = '\0';
    }
}

static void set_text(const config_file_t *cf, char *dst, key_id_t id)
{
    if (cf->values[id].set) {
        size_t len = strnlen(cf->values[id].text, WSG_CONFIG_STRING_MAX - 1);
        memcpy(dst, cf->values[id].text, len); /* checked shorter on load */
        dst[len] = '\0';
    }
}

void config_file_apply(const config_file_t *cf, wsg_config_t *cfg)
{
    if (cf == NULL) {
        return;
    }
    const value_t *v = cf->values;
    set_text(cf, cfg->tag, DEV_TAG);
    set_text(cf, cfg->version, DEV_VERSION);
    if (v[DEV_SERIAL].set) {
        cfg->serial = (uint32_t)v[DEV_SERIAL].number;
    }
    for (unsigned i = 0; i < SETTINGS_TABLE_COUNT; i++) {
        /* the [network] ones reach the device through the options */
        const settings_row_t *row = &settings_table[i];
        if (cf->settings[i].set && strcmp(row->ini_section, "motion") == 0) {
            wsg_config_setting_put(cfg, row->id, (float)cf->settings[i].number);
        }
    }
    if (v[MOT_HOMING].set) {
        cfg->home_positive = v[MOT_HOMING].number != 0.0;
    }
    if (v[MOT_MOVE_RETARGET].set) {
        cfg->move_retarget = v[MOT_MOVE_RETARGET].number != 0.0;
    }
    /* disconnect_faststop reaches the device through the options */
}
