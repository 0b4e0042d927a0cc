/* SPDX-License-Identifier: BSD-3-Clause */
/* config_file_save(): the settings in force back into the INI file, line by
 * line, so that comments, order and every other key survive. */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <unistd.h>

#include "config_file.h"
#include "settings_table.h"
#include "text_file.h"

#define SAVE_KEYS_MAX 16
#define FILE_LINE_MAX 4096
#define FILE_BYTES_MAX (1u << 20)

typedef struct {
    char section[24];
    const char *key;
    char value[80]; /* a number, a quoted tag, a "/user/NAME" path (NAME: 64 at most) */
    bool written;
} save_key_t;

typedef struct {
    save_key_t keys[SAVE_KEYS_MAX];
    unsigned count;
} save_set_t;

/* The shortest decimal that reads back as the same float. */
static void format_float(float value, char *out, size_t cap)
{
    for (int digits = 6; digits <= 9; digits++) {
        snprintf(out, cap, "%.*g", digits, (double)value);
        if ((float)strtod(out, NULL) == value) {
            return;
        }
    }
}

static save_key_t *add(save_set_t *set, const char *section, const char *key)
{
    save_key_t *k = &set->keys[set->count++];
    snprintf(k->section, sizeof(k->section), "%s", section);
    k->key = key;
    k->written = false;
    return k;
}

static void add_float(save_set_t *set, const char *section, const char *key, float value)
{
    format_float(value, add(set, section, key)->value, sizeof(set->keys[0].value));
}

static void add_bool(save_set_t *set, const char *section, const char *key, bool value)
{
    snprintf(add(set, section, key)->value, sizeof(set->keys[0].value), "%s", value ? "yes" : "no");
}

static void collect(save_set_t *set, unsigned device, const wsg_config_t *cfg)
{
    for (unsigned i = 0; i < SETTINGS_TABLE_COUNT; i++) {
        const settings_row_t *row = &settings_table[i];
        float value = wsg_config_setting_get(cfg, row->id);
        if (row->ini_key == NULL) {
            continue; /* not a setting of the file */
        }
        if (settings_table_is_switch(row)) {
            add_bool(set, row->ini_section, row->ini_key, value != 0.0f);
        } else {
            add_float(set, row->ini_section, row->ini_key, value);
        }
    }
    char section[24] = "device";
    if (device > 0) {
        snprintf(section, sizeof(section), "device.%u", device);
    }
    /* quoted as it is: the device holds no '"' or control character in it
     * (wsg_config_text_char_ok, the file's own rule) */
    snprintf(add(set, section, "tag")->value, sizeof(set->keys[0].value), "\"%s\"", cfg->tag);
}

static void put_missing(FILE *out, save_set_t *set, const char *section)
{
    for (unsigned i = 0; i < set->count; i++) {
        save_key_t *k = &set->keys[i];
        if (!k->written && strcasecmp(k->section, section) == 0) {
            fprintf(out, "%s = %s\n", k->key, k->value);
            k->written = true;
        }
    }
}

/* "[name]" -> name; false for any other line. */
static bool section_header(const char *line, char *name, size_t cap)
{
    const char *p = line + strspn(line, " \t");
    const char *end = strchr(p, ']');
    if (*p != '[' || end == NULL) {
        return false;
    }
    snprintf(name, cap, "%.*s", (int)(end - p - 1), p + 1);
    return true;
}

/* The key of a key line in section, or NULL. A key line is what libinih
 * takes for one: not a comment or section header, its name running to the
 * first '=' or ':' ("key = value" and "key : value" alike). A line the
 * loader reads as a key must be one here, or it outlives the saved value. */
static save_key_t *key_line(save_set_t *set, const char *section, const char *line)
{
    const char *p = line + strspn(line, " \t");
    size_t sep = strcspn(p, "=:");
    if (*p == ';' || *p == '#' || *p == '[' || p[sep] == '\0') {
        return NULL;
    }
    size_t len = sep;
    while (len > 0 && (p[len - 1] == ' ' || p[len - 1] == '\t')) {
        len--;
    }
    for (unsigned i = 0; i < set->count; i++) {
        save_key_t *k = &set->keys[i];
        if (strcasecmp(k->section, section) == 0 && strlen(k->key) == len &&
            strncasecmp(k->key, p, len) == 0) {
            return k;
        }
    }
    return NULL;
}

/* A line's text without the CRs at its end: "\n" alone ends every line
 * written, and a CR left before it (of "\r\r\n") is line-end debris that a
 * copy would turn into a CRLF end, read differently by the next save. */
static size_t text_length(const char *line)
{
    size_t len = strlen(line);
    while (len > 0 && line[len - 1] == '\r') {
        len--;
    }
    return len;
}

/* Device 0's tag goes to [device] unless the file gives device 0 a tag in a
 * [device.0] section, which wins at the next start: it is saved there. */
static void tag_where_it_counts(const config_file_t *cf, save_set_t *set, unsigned device)
{
    for (unsigned i = 0; i < set->count && device == 0 && config_file_device_sets_tag(cf, 0); i++) {
        if (strcmp(set->keys[i].key, "tag") == 0) {
            snprintf(set->keys[i].section, sizeof(set->keys[i].section), "device.0");
        }
    }
}

/* The first lines of a save file wsgsim creates. */
#define NEW_FILE_HEADER                                                                            \
    "# The settings the wsgsim web page saved (Save). wsgsim reads this file\n"                    \
    "# after its --config file: what it sets overrides that file's value.\n"                       \
    "# Remove it to return to the --config file's settings.\n"

/* Copies the file (in; NULL: a new file), each key to save in place, the
 * missing ones at the end of their section. */
static bool rewrite(text_file_t *in, FILE *out, save_set_t *set)
{
    char section[64] = "";
    text_file_read_t got = TEXT_FILE_END;
    if (in == NULL) {
        fputs(NEW_FILE_HEADER, out);
    }
    while (in != NULL && (got = text_file_next(in)) == TEXT_FILE_LINE) {
        char name[64];
        if (section_header(in->line, name, sizeof(name))) {
            put_missing(out, set, section);
            snprintf(section, sizeof(section), "%s", name);
        }
        save_key_t *k = key_line(set, section, in->line);
        if (k != NULL && !k->written) {
            fprintf(out, "%s = %s\n", k->key, k->value);
            k->written = true;
        } else if (k == NULL) {
            fprintf(out, "%.*s\n", (int)text_length(in->line), in->line);
        }
    }
    put_missing(out, set, section);
    for (unsigned i = 0; i < set->count; i++) {
        if (!set->keys[i].written) {
            fprintf(out, "\n[%s]\n", set->keys[i].section);
            put_missing(out, set, set->keys[i].section);
        }
    }
    return got == TEXT_FILE_END;
}

/* Flushes, syncs and closes out; false with errno of the first failure. */
static bool close_synced(FILE *out)
{
    bool ok = fflush(out) == 0 && fsync(fileno(out)) == 0;
    int first_errno = errno;
    if (fclose(out) != 0) {
        return false;
    }
    errno = first_errno;
    return ok;
}

/* Writes tmp from path (or from nothing when path does not exist yet),
 * synced to disk; false with the reason in why. */
static bool write_copy(const char *path, const char *tmp, save_set_t *set, char *why, size_t cap)
{
    struct stat st;
    bool stat_ok = stat(path, &st) == 0;
    bool exists = stat_ok || errno != ENOENT;
    text_file_t in;
    if (exists && !text_file_open(&in, path, "settings", FILE_LINE_MAX, FILE_BYTES_MAX)) {
        snprintf(why, cap, "cannot read %s", path);
        return false;
    }
    FILE *out = fopen(tmp, "w");
    bool copied = out != NULL && rewrite(exists ? &in : NULL, out, set);
    bool ok = out != NULL && close_synced(out) && copied;
    int write_errno = errno;
    if (exists) {
        text_file_close(&in);
    }
    if (ok && stat_ok) {
        chmod(tmp, st.st_mode & 07777);
    }
    if (!ok) {
        snprintf(why, cap, "cannot write %s: %s", path, strerror(write_errno));
    }
    return ok;
}

/* Device 0's startup script is [script] startup (with autostart), another
 * device's [device.N] script; a fleet device has no autostart of its own,
 * so "none" is kept only for device 0. */
static void collect_startup(save_set_t *set, unsigned device, const char *startup)
{
    size_t cap = sizeof(set->keys[0].value);
    if (startup == NULL || (startup[0] == '\0' && device > 0)) {
        return;
    }
    if (device > 0) {
        char section[24];
        snprintf(section, sizeof(section), "device.%u", device);
        snprintf(add(set, section, "script")->value, cap, "%s", startup);
        return;
    }
    if (startup[0] != '\0') {
        snprintf(add(set, "script", "startup")->value, cap, "%s", startup);
    }
    add_bool(set, "script", "autostart", startup[0] != '\0');
}

bool config_file_save(const config_file_t *cf, const char *path, unsigned device,
                      const wsg_config_t *cfg, const char *startup, char *why, size_t cap)
{
    if (!config_file_motion_fits(cf, cfg, why, cap)) {
        return false; /* the next start would refuse the file */
    }
    save_set_t set = {.count = 0};
    collect(&set, device, cfg);
    tag_where_it_counts(cf, &set, device);
    collect_startup(&set, device, startup);
    char tmp[4096];
    snprintf(tmp, sizeof(tmp), "%s.saving", path);
    if (!write_copy(path, tmp, &set, why, cap)) {
        remove(tmp);
        return false;
    }
    if (rename(tmp, path) != 0) {
        snprintf(why, cap, "cannot write %s: %s", path, strerror(errno));
        remove(tmp);
        return false;
    }
    return true;
}
