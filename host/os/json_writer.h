/* SPDX-License-Identifier: BSD-3-Clause */
/* JSON written straight into one growing buffer: the state and its event
 * stream are built several times a second for every watcher, so they skip
 * a tree of objects and printf (cJSON's tree and "%g" cost ten times the
 * text). Numbers are written as the device writes them (the core's
 * fixed-point formatter: at most three decimals, its resolution). A key is
 * NULL inside an array. Out of memory sets failed; the text is then
 * incomplete and json_writer_take() returns NULL. Keys are the program's own
 * names and are written unescaped; string values are escaped. */
#ifndef HOST_JSON_WRITER_H
#define HOST_JSON_WRITER_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

typedef struct json_writer {
    char *data;
    size_t len;
    size_t cap;
    bool failed;
    bool first; /* no value yet in the innermost object or array */
} json_writer_t;

/* An empty writer; it allocates on the first write. */
void json_writer_init(json_writer_t *j);
/* The text, NUL-terminated, for the caller to free(), and its length in
 * *len unless len is NULL; NULL if a write failed. The writer is empty
 * again. */
char *json_writer_take(json_writer_t *j, size_t *len);
void json_writer_free(json_writer_t *j);

/* Raw text, no separator: a prefix before the JSON (an event's header). */
void json_writer_raw(json_writer_t *j, const char *text, size_t len);

void json_writer_open_object(json_writer_t *j, const char *key);
void json_writer_close_object(json_writer_t *j);
void json_writer_open_array(json_writer_t *j, const char *key);
void json_writer_close_array(json_writer_t *j);

void json_writer_float(json_writer_t *j, const char *key, float value);
void json_writer_uint(json_writer_t *j, const char *key, uint64_t value);
/* Microseconds as milliseconds, exactly: 1500 -> 1.5. */
void json_writer_ms(json_writer_t *j, const char *key, uint64_t us);
void json_writer_bool(json_writer_t *j, const char *key, bool value);
/* A string, escaped; NULL writes null. */
void json_writer_string(json_writer_t *j, const char *key, const char *value);
void json_writer_null(json_writer_t *j, const char *key);
/* A number as cJSON writes one: the shortest of 15 or 17 significant
 * digits that reads back the same (for the few values that are no
 * reading: a clock's scale). */
void json_writer_double(json_writer_t *j, const char *key, double value);
/* A value already written as JSON text (another writer's), under key. */
void json_writer_raw_value(json_writer_t *j, const char *key, const char *json);

#endif
