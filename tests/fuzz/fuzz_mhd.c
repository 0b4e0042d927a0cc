/* SPDX-License-Identifier: BSD-3-Clause */
/* The web targets' stand-in for libmicrohttpd (fuzz_mhd.h): the part of it
 * the routes call, and one request through the routes with its reply
 * checked: exactly one response per request, a valid HTTP status, and a
 * body that is a JSON object whenever it says application/json. An event
 * stream is read once (its first event) and then closed, as by a client
 * that goes away. */
#include "fuzz_mhd.h"

#include <stdlib.h>
#include <string.h>

#include <cjson/cJSON.h>
#include <microhttpd.h>

#include "fleet.h"
#include "fuzz_host.h"
#include "clock.h"
#include "web/web_lines.h"
#include "web/web_routes.h"

#define EVENT_READ_MAX 65536u

/* The fake's response: a buffer or an event-stream reader, with MHD's
 * reference count (the route's, plus the connection's once queued). */
struct MHD_Response {
    unsigned refs;
    char *bytes;
    size_t len;
    bool owned;
    bool json;
    MHD_ContentReaderCallback reader;
    void *reader_ctx;
    MHD_ContentReaderFreeCallback reader_free;
};

/* The fake connection: its query arguments ("k=v" strings, as MHD splits
 * and decodes them) and what the route queued on it. */
#define ARGS_MAX 8
struct MHD_Connection {
    const char *args[ARGS_MAX];
    unsigned arg_count;
    struct MHD_Response *queued;
    unsigned status;
    bool suspended;
};

static const char *forbidden; /* fuzz_mhd_forbid() */

static const char *const methods[8] = {"GET",    "POST",  "HEAD",    "PUT",
                                       "DELETE", "PATCH", "OPTIONS", "get"};
static const uint32_t run_ms[16] = {0,   0,   1,   5,    10,   20,   50,   100,
                                    200, 300, 500, 1000, 2000, 3000, 5000, 10000};

struct MHD_Response *MHD_create_response_from_buffer(size_t size, void *buffer,
                                                     enum MHD_ResponseMemoryMode mode)
{
    struct MHD_Response *r = calloc(1, sizeof(*r));
    if (r == NULL) {
        abort();
    }
    r->refs = 1;
    r->bytes = buffer;
    r->len = size;
    r->owned = mode == MHD_RESPMEM_MUST_FREE;
    if (mode == MHD_RESPMEM_MUST_COPY) {
        abort(); /* the routes never ask for a copy */
    }
    return r;
}

struct MHD_Response *MHD_create_response_from_callback(uint64_t size, size_t block_size,
                                                       MHD_ContentReaderCallback crc, void *crc_cls,
                                                       MHD_ContentReaderFreeCallback crfc)
{
    (void)size;
    (void)block_size;
    struct MHD_Response *r = MHD_create_response_from_buffer(0, NULL, MHD_RESPMEM_PERSISTENT);
    r->reader = crc;
    r->reader_ctx = crc_cls;
    r->reader_free = crfc;
    return r;
}

enum MHD_Result MHD_add_response_header(struct MHD_Response *response, const char *header,
                                        const char *content)
{
    if (header == NULL || content == NULL || strpbrk(content, "\r\n") != NULL) {
        abort(); /* a header line must not break the reply */
    }
    if (strcmp(header, MHD_HTTP_HEADER_CONTENT_TYPE) == 0) {
        response->json = strcmp(content, "application/json") == 0;
    }
    return MHD_YES;
}

void MHD_destroy_response(struct MHD_Response *response)
{
    if (response == NULL || response->refs == 0) {
        abort();
    }
    if (--response->refs > 0) {
        return;
    }
    if (response->owned) {
        free(response->bytes);
    }
    if (response->reader_free != NULL) {
        response->reader_free(response->reader_ctx);
    }
    free(response);
}

enum MHD_Result MHD_queue_response(struct MHD_Connection *connection, unsigned int status_code,
                                   struct MHD_Response *response)
{
    if (connection->queued != NULL || status_code < 100 || status_code > 599) {
        abort(); /* one reply per request, with a real status */
    }
    response->refs++;
    connection->queued = response;
    connection->status = status_code;
    return MHD_YES;
}

const char *MHD_lookup_connection_value(struct MHD_Connection *connection, enum MHD_ValueKind kind,
                                        const char *key)
{
    size_t key_len = key != NULL ? strlen(key) : 0;
    for (unsigned i = 0; kind == MHD_GET_ARGUMENT_KIND && i < connection->arg_count; i++) {
        const char *arg = connection->args[i];
        if (key != NULL && strncmp(arg, key, key_len) == 0 && arg[key_len] == '=') {
            return arg + key_len + 1;
        }
    }
    return NULL; /* no header reaches the routes: the server's side checks them */
}

/* "path?a=1&b=2": the URL cut at '?' and its arguments split at '&'. */
static void split_query(char *url, struct MHD_Connection *connection)
{
    char *query = strchr(url, '?');
    if (query == NULL) {
        return;
    }
    *query++ = '\0';
    for (char *arg = strtok(query, "&"); arg != NULL && connection->arg_count < ARGS_MAX;
         arg = strtok(NULL, "&")) {
        connection->args[connection->arg_count++] = arg;
    }
}

void MHD_suspend_connection(struct MHD_Connection *connection)
{
    connection->suspended = true;
}

void MHD_resume_connection(struct MHD_Connection *connection)
{
    connection->suspended = false;
}

static void check_json(const struct MHD_Response *r)
{
    char *text = malloc(r->len + 1u);
    if (text == NULL) {
        abort();
    }
    memcpy(text, r->bytes, r->len);
    text[r->len] = '\0';
    cJSON *json = cJSON_Parse(text);
    if (strlen(text) != r->len || !cJSON_IsObject(json)) {
        abort(); /* a JSON reply is one JSON object */
    }
    cJSON_Delete(json);
    free(text);
}

/* A client reads the stream's first event, then goes away. */
static void read_stream(struct MHD_Connection *connection, struct MHD_Response *r)
{
    char buf[4096];
    size_t total = 0;
    while (!connection->suspended && total < EVENT_READ_MAX) {
        ssize_t n = r->reader(r->reader_ctx, total, buf, sizeof(buf));
        if (n < 0 || n == 0) {
            break; /* the end, or it waits for the next tick */
        }
        total += (size_t)n;
    }
    if (total == 0) {
        abort(); /* the first event comes at once */
    }
}

static void finish_request(struct MHD_Connection *connection, enum MHD_Result result)
{
    struct MHD_Response *r = connection->queued;
    if (result != MHD_YES || r == NULL) {
        abort(); /* every request is answered */
    }
    if (r->json) {
        check_json(r);
    }
    if (forbidden != NULL && r->len > 0 && memmem(r->bytes, r->len, forbidden, strlen(forbidden))) {
        abort(); /* a reply quotes what it must never show */
    }
    if (r->reader != NULL) {
        read_stream(connection, r);
    }
    MHD_destroy_response(r); /* the connection's reference */
}

void fuzz_mhd_request(web_app_t *app, const uint8_t *p, size_t n, const char *url_prefix)
{
    static char url[4096 + 1];
    static char body[WEB_BODY_MAX + 1u];
    if (n == 0) {
        return;
    }
    const uint8_t *url_end = memchr(p + 1, '\n', n - 1);
    size_t url_len = url_end != NULL ? (size_t)(url_end - (p + 1)) : n - 1;
    size_t body_at = url_end != NULL ? url_len + 2u : n;
    size_t body_len = n - body_at < WEB_BODY_MAX ? n - body_at : WEB_BODY_MAX;
    size_t prefix_len = strlen(url_prefix);
    if (prefix_len + url_len >= sizeof(url)) {
        url_len = sizeof(url) - 1u - prefix_len;
    }
    memcpy(url, url_prefix, prefix_len);
    memcpy(url + prefix_len, p + 1, url_len);
    url[prefix_len + url_len] = '\0';
    memcpy(body, p + body_at, body_len);
    body[body_len] = '\0';
    struct MHD_Connection connection = {.queued = NULL, .arg_count = 0};
    split_query(url, &connection);
    web_request_t req = {app,  &connection, methods[p[0] & 7u], url,
                         body, body_len,    (p[0] & 8u) != 0,   fuzz_host_sim()};
    finish_request(&connection, web_routes_dispatch(&req));
    if (!simclock_paused(simctl_clock(fuzz_host_sim()))) {
        simclock_pause(simctl_clock(fuzz_host_sim())); /* a resume lets wall time in */
    }
    fuzz_host_settle();
    if (run_ms[p[0] >> 4] > 0) {
        fuzz_host_step((uint64_t)run_ms[p[0] >> 4] * 1000u);
    }
}

void fuzz_mhd_forbid(const char *text)
{
    forbidden = text;
}

void fuzz_mhd_app_start(web_app_t *app, const host_options_t *opts)
{
    web_app_init(app, NULL);
    web_lines_enable(&app->lines, (unsigned)opts->devices); /* as the server does */
    fuzz_host_start(opts);
    app->fleet = fuzz_host_fleet(); /* as web_server_start() is given it */
    app->sim = fuzz_host_sim();
    for (unsigned i = 0; i < fleet_count(app->fleet); i++) { /* as main does */
        web_lines_attach(&app->lines, &fleet_gripper(app->fleet, i)->device, i);
    }
}

void fuzz_mhd_app_stop(web_app_t *app)
{
    web_app_release(app); /* as the server stops: before the devices go */
    fuzz_host_stop();
}
