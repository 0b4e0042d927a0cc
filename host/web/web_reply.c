/* SPDX-License-Identifier: BSD-3-Clause */
/* Replies and request bodies: what every route uses. */
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "hal_clock.h"
#include "sim/sim_world.h"
#include "wsg/wsg_names.h"
#include "web/web_internal.h"

enum MHD_Result web_reply_bytes(const web_request_t *req, unsigned http_status,
                                const char *content_type, const void *bytes, size_t len)
{
    struct MHD_Response *response =
        MHD_create_response_from_buffer(len, (void *)bytes, MHD_RESPMEM_PERSISTENT);
    if (response == NULL) {
        return MHD_NO;
    }
    MHD_add_response_header(response, MHD_HTTP_HEADER_CONTENT_TYPE, content_type);
    enum MHD_Result result = MHD_queue_response(req->connection, http_status, response);
    MHD_destroy_response(response);
    return result;
}

static enum MHD_Result reply_text(const web_request_t *req, unsigned http_status, char *text,
                                  const char *allow)
{
    if (text == NULL) {
        return MHD_NO;
    }
    struct MHD_Response *response =
        MHD_create_response_from_buffer(strlen(text), text, MHD_RESPMEM_MUST_FREE);
    if (response == NULL) {
        free(text);
        return MHD_NO;
    }
    MHD_add_response_header(response, MHD_HTTP_HEADER_CONTENT_TYPE, "application/json");
    MHD_add_response_header(response, MHD_HTTP_HEADER_CACHE_CONTROL, "no-store");
    if (allow != NULL) {
        MHD_add_response_header(response, MHD_HTTP_HEADER_ALLOW, allow);
    }
    enum MHD_Result result = MHD_queue_response(req->connection, http_status, response);
    MHD_destroy_response(response);
    return result;
}

enum MHD_Result web_reply_json_text(const web_request_t *req, unsigned http_status, char *text)
{
    return reply_text(req, http_status, text, NULL);
}

enum MHD_Result web_reply_json(const web_request_t *req, unsigned http_status, cJSON *json)
{
    char *text = json != NULL ? cJSON_PrintUnformatted(json) : NULL;
    cJSON_Delete(json);
    return reply_text(req, http_status, text, NULL);
}

static cJSON *error_json(wsg_status_t status, const char *fmt, va_list args)
{
    char message[256];
    vsnprintf(message, sizeof(message), fmt, args);
    cJSON *j = cJSON_CreateObject();
    cJSON_AddStringToObject(j, "error", wsg_status_name(status));
    cJSON_AddNumberToObject(j, "code", status);
    cJSON_AddStringToObject(j, "message", message);
    return j;
}

enum MHD_Result web_reply_error(const web_request_t *req, unsigned http_status, wsg_status_t status,
                                const char *fmt, ...)
{
    va_list args;
    va_start(args, fmt);
    cJSON *j = error_json(status, fmt, args);
    va_end(args);
    return web_reply_json(req, http_status, j);
}

enum MHD_Result web_reply_wrong_method(const web_request_t *req, const char *allowed)
{
    char *text = NULL;
    cJSON *j = cJSON_CreateObject();
    char message[96];
    snprintf(message, sizeof(message), "%s is not allowed here; use %s", req->method, allowed);
    cJSON_AddStringToObject(j, "error", wsg_status_name(E_CMD_UNKNOWN));
    cJSON_AddNumberToObject(j, "code", E_CMD_UNKNOWN);
    cJSON_AddStringToObject(j, "message", message);
    text = cJSON_PrintUnformatted(j);
    cJSON_Delete(j);
    return reply_text(req, MHD_HTTP_METHOD_NOT_ALLOWED, text, allowed);
}

enum MHD_Result web_reply_redirect(const web_request_t *req, const char *location)
{
    struct MHD_Response *response =
        MHD_create_response_from_buffer(0, NULL, MHD_RESPMEM_PERSISTENT);
    if (response == NULL) {
        return MHD_NO;
    }
    MHD_add_response_header(response, MHD_HTTP_HEADER_LOCATION, location);
    enum MHD_Result result = MHD_queue_response(req->connection, MHD_HTTP_FOUND, response);
    MHD_destroy_response(response);
    return result;
}

/* A NUL in the text, as a byte or as the escape \u0000: cJSON keeps strings
 * NUL-terminated, so "abc\u0000def" would silently become "abc". Escapes
 * stand only inside strings, and each is skipped whole (\\u0000 is a
 * backslash and "u0000"). */
static bool holds_nul(const char *text, size_t len)
{
    for (size_t i = 0; i < len; i++) {
        if (text[i] == '\0') {
            return true;
        }
        if (text[i] == '\\' && i + 1 < len) {
            if (text[i + 1] == 'u' && len - i >= 6 && strncmp(text + i + 2, "0000", 4) == 0) {
                return true;
            }
            i++;
        }
    }
    return false;
}

/* Only white space may follow the object. */
static bool ends_after(const char *end)
{
    return end != NULL && end[strspn(end, " \t\r\n")] == '\0';
}

cJSON *web_body_object(const web_request_t *req, enum MHD_Result *result)
{
    if (req->body_len == 0) {
        return cJSON_CreateObject();
    }
    if (holds_nul(req->body, req->body_len)) {
        *result = web_reply_error(req, MHD_HTTP_BAD_REQUEST, E_CMD_FORMAT_ERROR,
                                  "the body holds a NUL character");
        return NULL;
    }
    const char *end = NULL;
    cJSON *body = cJSON_ParseWithOpts(req->body, &end, false);
    if (!cJSON_IsObject(body) || !ends_after(end)) {
        cJSON_Delete(body);
        *result = web_reply_error(req, MHD_HTTP_BAD_REQUEST, E_CMD_FORMAT_ERROR,
                                  "the body must be one JSON object");
        return NULL;
    }
    return body;
}

static const cJSON *field(const cJSON *body, const char *name)
{
    return cJSON_GetObjectItemCaseSensitive(body, name);
}

bool web_field_number(const web_request_t *req, const cJSON *body, const char *name, bool required,
                      double *out, bool *given, enum MHD_Result *result)
{
    const cJSON *item = field(body, name);
    if (given != NULL) {
        *given = item != NULL;
    }
    if (item == NULL && required) {
        *result =
            web_reply_error(req, MHD_HTTP_BAD_REQUEST, E_NOT_ENOUGH_PARAMS, "%s: missing", name);
        return false;
    }
    if (item != NULL && (!cJSON_IsNumber(item) || !isfinite(item->valuedouble))) {
        *result = web_reply_error(req, MHD_HTTP_BAD_REQUEST, E_INVALID_PARAMETER,
                                  "%s: must be a number", name);
        return false;
    }
    if (item != NULL) {
        *out = item->valuedouble;
    }
    return true;
}

bool web_field_bool(const web_request_t *req, const cJSON *body, const char *name, bool *out,
                    bool *given, enum MHD_Result *result)
{
    const cJSON *item = field(body, name);
    *given = item != NULL;
    if (item != NULL && !cJSON_IsBool(item)) {
        *result = web_reply_error(req, MHD_HTTP_BAD_REQUEST, E_INVALID_PARAMETER,
                                  "%s: must be true or false", name);
        return false;
    }
    if (item != NULL) {
        *out = cJSON_IsTrue(item);
    }
    return true;
}

bool web_field_string(const web_request_t *req, const cJSON *body, const char *name,
                      const char **out, bool *given, enum MHD_Result *result)
{
    const cJSON *item = field(body, name);
    *given = item != NULL;
    if (item != NULL && !cJSON_IsString(item)) {
        *result = web_reply_error(req, MHD_HTTP_BAD_REQUEST, E_INVALID_PARAMETER,
                                  "%s: must be a string", name);
        return false;
    }
    if (item != NULL) {
        *out = item->valuestring;
    }
    return true;
}

bool web_fields_known(const web_request_t *req, const cJSON *body, const char *const *names,
                      enum MHD_Result *result)
{
    for (const cJSON *item = body->child; item != NULL; item = item->next) {
        bool known = false;
        for (unsigned i = 0; names[i] != NULL && !known; i++) {
            known = strcmp(names[i], item->string) == 0;
        }
        if (!known) {
            *result = web_reply_error(req, MHD_HTTP_BAD_REQUEST, E_INVALID_PARAMETER,
                                      "%s: unknown field", item->string);
            return false;
        }
    }
    return true;
}

void web_device_sense(gripper_t *g)
{
    wsg_sim_world_advance(&g->world, hal_clock_now_us());
    wsg_device_sense(&g->device);
}

bool web_since_argument(const web_request_t *req, uint64_t *since, enum MHD_Result *result)
{
    const char *text = MHD_lookup_connection_value(req->connection, MHD_GET_ARGUMENT_KIND, "since");
    char *end = NULL;
    errno = 0;
    *since = text != NULL ? strtoull(text, &end, 10) : 0u;
    /* strtoull takes "-1" (as the largest number) and saturates */
    if (text != NULL &&
        (end == text || *end != '\0' || strspn(text, "0123456789") == 0 || errno == ERANGE)) {
        *result = web_reply_error(req, MHD_HTTP_BAD_REQUEST, E_INVALID_PARAMETER,
                                  "since: expected a line number");
        return false;
    }
    return true;
}
