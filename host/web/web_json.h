/* SPDX-License-Identifier: BSD-3-Clause */
/* JSON written straight into one growing buffer: the state and its event
 * stream are built several times a second for every watcher, so they skip
 * a tree of objects and printf (cJSON's tree and "%g" cost ten times the
 * text). Numbers are written as the device writes them (the core's
 * fixed-point formatter: at most three decimals, its resolution). A key is
 * NULL inside an array. Out of memory sets failed; the text is then
 * incomplete and web_json_take() returns NULL. Keys are the program's own
 * names and are written unescaped; string values are escaped. */
#ifndef HOST_WEB_JSON_H
#define HOST_WEB_JSON_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

typedef struct web_json {
    char *data;
    size_t len;
    size_t cap;
    bool failed;
    bool first; /* no value yet in the innermost object or array */
} web_json_t;

/* An empty writer; it allocates on the first write. */
void web_json_init(web_json_t *j);
/* The text, NUL-terminated, for the caller to free(), and its length in
 * *len unless len is NULL; NULL if a write failed. The writer is empty
 * again. */
char *web_json_take(web_json_t *j, size_t *len);
void web_json_free(web_json_t *j);

/* Raw text, no separator: a prefix before the JSON (an event's header). */
void web_json_raw(web_json_t *j, const char *text, size_t len);

void web_json_open_object(web_json_t *j, const char *key);
void web_json_close_object(web_json_t *j);
void web_json_open_array(web_json_t *j, const char *key);
void web_json_close_array(web_json_t *j);

void web_json_float(web_json_t *j, const char *key, float value);
void web_json_uint(web_json_t *j, const char *key, uint64_t value);
/* Microseconds as milliseconds, exactly: 1500 -> 1.5. */
void web_json_ms(web_json_t *j, const char *key, uint64_t us);
void web_json_bool(web_json_t *j, const char *key, bool value);
/* A string, escaped; NULL writes null. */
void web_json_string(web_json_t *j, const char *key, const char *value);
void web_json_null(web_json_t *j, const char *key);

#endif
