/* SPDX-License-Identifier: BSD-3-Clause */
#include "config_file.h"

#include <errno.h>
#include <ini.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>

#include "config_file_internal.h"
#include "config_value.h"
#include "text_file.h"

#define FILE_LINE_MAX 4096        /* a comment line may be this long */
#define FILE_BYTES_MAX (1u << 20) /* a device configuration is a few KiB */

/* The device's own keys (key_id_t); the options' keys are option_table's,
 * the device settings' settings_table's. */
static const struct {
    const char *section;
    const char *name;
    config_value_kind_t kind;
    double min, max; /* a CV_NUMBER's range; the other kinds check their own */
} keys[KEY_COUNT] = {
    [DEV_SERIAL] = {"device", "serial", CV_SERIAL, 0, 0},
    [DEV_TAG] = {"device", "tag", CV_TEXT, 0, 0},
    [DEV_VERSION] = {"device", "firmware_version", CV_TEXT, 0, 0},
    [DEV_HW_REVISION] = {"device", "hardware_revision", CV_BYTE, 0, 0},
    [MOT_HOMING] = {"motion", "homing_direction", CV_DIRECTION, 0, 0},
    [MOT_MOVE_RETARGET] = {"motion", "move_retarget", CV_BOOL, 0, 0},
    /* [mechanics] (wsg_mechanics_t): mm/s, a share, mm/s^2, N/s, ms */
    [MECH_SPEED_LIMIT] = {"mechanics", "speed_limit", CV_NUMBER, 1, 1000},
    [MECH_ACCEL_SCALE] = {"mechanics", "acceleration_scale", CV_NUMBER, 0.1, 10},
    [MECH_HOMING_SPEED] = {"mechanics", "homing_speed", CV_NUMBER, 1, 1000},
    [MECH_STOP_DECEL] = {"mechanics", "stop_deceleration", CV_NUMBER, 0, 100000},
    [MECH_FAST_STOP_DECEL] = {"mechanics", "fast_stop_deceleration", CV_NUMBER, 10, 100000},
    [MECH_FORCE_RISE] = {"mechanics", "force_rise", CV_NUMBER, 0, 1000000},
    [MECH_SETTLE] = {"mechanics", "settle_time", CV_NUMBER, 0.001, 10000},
    [MECH_BLOCK_DETECT] = {"mechanics", "block_detect_time", CV_NUMBER, 0.001, 10000},
    [MECH_HOME_BLOCK_DETECT] = {"mechanics", "home_block_detect_time", CV_NUMBER, 0.001, 10000},
    [MECH_PART_LOST] = {"mechanics", "part_lost_time", CV_NUMBER, 0.001, 10000},
};

/* A [mechanics] number outside its range: why, in why; NULL when fine. */
static const char *out_of_range(unsigned key, const value_t *v, char *why, size_t cap)
{
    if (keys[key].kind != CV_NUMBER || (v->number >= keys[key].min && v->number <= keys[key].max)) {
        return NULL;
    }
    snprintf(why, cap, "%s is outside %g..%g", v->text, keys[key].min, keys[key].max);
    return why;
}

static const struct {
    const char *name;
    config_value_kind_t kind;
} sec_keys[SEC_KEY_COUNT] = {
    [SEC_MODEL] = {"model", CV_MODEL},
    [SEC_SERIAL] = {"serial", CV_SERIAL},
    [SEC_TAG] = {"tag", CV_TEXT},
    [SEC_TCP_PORT] = {"tcp_port", CV_PORT},
    [SEC_UDP_PORT] = {"udp_port", CV_PORT},
    [SEC_SCRIPT] = {"script", CV_PATH},
    [SEC_FINGERS] = {"fingers", CV_FINGERS},
};

#define DEVICE_SECTION "device."

/* What the parser is doing: the reader counts lines for the handler. */
typedef struct {
    text_file_t file;
    config_file_t *cf; /* what it reads into */
    const char *path;  /* one of cf->files */
    int line;
    bool failed;
    char why[CONFIG_VALUE_WHY_MAX]; /* the last value's reason */
} parse_state_t;

bool config_file_fail_at(const char *path, int line, const char *section, const char *name,
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

/* One value of a key, by its kind (config_value.h); NULL when fine, else
 * why not. */
static const char *read_value(parse_state_t *st, config_value_kind_t kind, const char *text,
                              value_t *v)
{
    config_value_t read;
    const char *why = config_value_convert(kind, text, &read);
    v->number = read.number;
    memcpy(v->text, read.text, sizeof(v->text));
    if (why == NULL) {
        return NULL;
    }
    snprintf(st->why, sizeof(st->why), "%s", why); /* read.why ends with read */
    return st->why;
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
    if (!plain || !config_value_int_range(digits, 0, HOST_DEVICES_MAX - 1, &n)) {
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
        return config_file_fail_at(st->path, st->line, section, name, why);
    }
    device_section_t *d = section_of(st->cf, index);
    for (unsigned k = 0; k < SEC_KEY_COUNT && d != NULL; k++) {
        if (strcasecmp(sec_keys[k].name, name) != 0) {
            continue;
        }
        const char *why = read_value(st, sec_keys[k].kind, text, &d->values[k]);
        if (why != NULL) {
            st->failed = true;
            return config_file_fail_at(st->path, st->line, section, name, why);
        }
        mark_set(&d->values[k], st);
        return 1;
    }
    st->failed = true;
    return config_file_fail_at(
        st->path, st->line, section, name,
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
        config_value_kind_t kind = settings_table_is_switch(row) ? CV_BOOL : CV_NUMBER;
        const char *why = read_value(st, kind, text, &st->cf->settings[i]);
        if (why != NULL) {
            st->failed = true;
            return config_file_fail_at(st->path, st->line, section, name, why);
        }
        mark_set(&st->cf->settings[i], st);
        return 1;
    }
    st->failed = true;
    return config_file_fail_at(st->path, st->line, section, name,
                               "unknown key (every key: " WSGSIM_EXAMPLE_CONFIG ")");
}

/* An option's key (option_table.h), else a device setting's. */
static int on_option_key(parse_state_t *st, const char *section, const char *name, const char *text)
{
    for (unsigned i = 0; i < OPTION_COUNT; i++) {
        const option_row_t *row = &option_table[i];
        if (strcasecmp(row->section, section) != 0 || strcasecmp(row->key, name) != 0) {
            continue;
        }
        const char *why = read_value(st, row->kind, text, &st->cf->options[i]);
        if (why != NULL) {
            st->failed = true;
            return config_file_fail_at(st->path, st->line, section, name, why);
        }
        mark_set(&st->cf->options[i], st);
        return 1;
    }
    return on_setting_key(st, section, name, text);
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
        char range[96];
        const char *why = read_value(st, keys[i].kind, text, &st->cf->values[i]);
        if (why == NULL) {
            why = out_of_range(i, &st->cf->values[i], range, sizeof(range));
        }
        if (why != NULL) {
            st->failed = true;
            return config_file_fail_at(st->path, st->line, section, name, why);
        }
        mark_set(&st->cf->values[i], st);
        return 1;
    }
    return on_option_key(st, section, name, text);
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

/* The options the files set, through the command line's own table, and
 * the two device settings that reach the devices through the options. */
static void apply_options(const config_file_t *cf, host_options_t *opts)
{
    for (unsigned i = 0; i < OPTION_COUNT; i++) {
        const value_t *v = &cf->options[i];
        if (v->set) {
            (void)option_set(opts, (option_id_t)i, v->number, v->text); /* checked on reading */
        }
    }
    const value_t *faststop = setting_value(cf, WSG_SET_DISCONNECT_FASTSTOP);
    if (faststop->set) {
        opts->disconnect_faststop = faststop->number != 0.0;
    }
    const value_t *crc = setting_value(cf, WSG_SET_BINARY_CRC_CHECK);
    if (crc->set) {
        opts->binary_crc = crc->number != 0.0;
    }
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
    apply_options(cf, opts);
    return true;
}
