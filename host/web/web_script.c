/* SPDX-License-Identifier: BSD-3-Clause */
/* The scripting routes (docs/web.md, docs/scripting.md): the device's
 * script (state, run, stop, console) and its /user/ store (list, read,
 * write, delete). Running, stopping and changing files move the gripper or
 * write on the host: they follow the simulation panel's rule (loopback
 * clients only unless --sim-bind names another address). */
#include <dirent.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "fleet.h"
#include "script.h"
#include "script_json.h"
#include "web/web_internal.h"

#define STORE_FILES_MAX 64u
#define CONSOLE_PAGE 1000u

static bool is_method(const web_request_t *req, const char *method)
{
    return strcmp(req->method, method) == 0;
}

static enum MHD_Result forbidden(const web_request_t *req)
{
    return web_reply_error(req, MHD_HTTP_FORBIDDEN, E_ACCESS_DENIED,
                           "scripts are run and stored for loopback clients only "
                           "(--sim-bind allows more)");
}

static enum MHD_Result get_script(const web_request_t *req, gripper_t *g)
{
    cJSON *j = script_json(g);
    const char *startup = g->opts->script;
    if (startup != NULL && g->opts->script_autostart) {
        cJSON_AddStringToObject(j, "startup", startup);
    } else {
        cJSON_AddNullToObject(j, "startup");
    }
    return web_reply_json(req, MHD_HTTP_OK, j);
}

static enum MHD_Result run_script(const web_request_t *req, gripper_t *g)
{
    enum MHD_Result result = MHD_NO;
    cJSON *body = web_body_object(req, &result);
    if (body == NULL) {
        return result;
    }
    static const char *const names[] = {"file", NULL};
    const char *file = NULL;
    bool given = false;
    if (!web_fields_known(req, body, names, &result) ||
        !web_field_string(req, body, "file", &file, &given, &result)) {
        cJSON_Delete(body);
        return result;
    }
    if (!given) {
        cJSON_Delete(body);
        return web_reply_error(req, MHD_HTTP_BAD_REQUEST, E_NOT_ENOUGH_PARAMS,
                               "file: the script to run is missing");
    }
    char why[512];
    fleet_note_scripting(req->app->fleet);
    bool ok = gripper_run_script(g, file, why, sizeof(why));
    cJSON_Delete(body);
    if (!ok) {
        return web_reply_error(req, MHD_HTTP_NOT_FOUND, E_NOT_FOUND, "%s", why);
    }
    return get_script(req, g);
}

static enum MHD_Result stop_script(const web_request_t *req, gripper_t *g)
{
    if (g->script == NULL || !script_stop(g->script)) {
        return web_reply_error(req, MHD_HTTP_CONFLICT, E_NOT_AVAILABLE, "no script runs");
    }
    gripper_touch(g);
    return get_script(req, g);
}

/* ?since=N: the console lines numbered N and later, and the next number. */
static enum MHD_Result get_console(const web_request_t *req, gripper_t *g)
{
    const char *since_text =
        MHD_lookup_connection_value(req->connection, MHD_GET_ARGUMENT_KIND, "since");
    char *end = NULL;
    unsigned long long since = since_text != NULL ? strtoull(since_text, &end, 10) : 0u;
    if (since_text != NULL && (end == since_text || *end != '\0')) {
        return web_reply_error(req, MHD_HTTP_BAD_REQUEST, E_INVALID_PARAMETER,
                               "since: expected a line number");
    }
    cJSON *j = cJSON_CreateObject();
    cJSON *lines = cJSON_AddArrayToObject(j, "lines");
    uint64_t next = 0;
    if (g->script != NULL) {
        const char *page[CONSOLE_PAGE];
        size_t n = script_console(g->script, since, page, CONSOLE_PAGE, &next);
        for (size_t i = 0; i < n; i++) {
            cJSON_AddItemToArray(lines, cJSON_CreateString(page[i]));
        }
    }
    cJSON_AddNumberToObject(j, "next", (double)next);
    return web_reply_json(req, MHD_HTTP_OK, j);
}

/* PUT .../script/startup {"file": "/user/NAME"} or {"file": null}: what
 * the next power-on runs. */
static enum MHD_Result set_startup(const web_request_t *req, gripper_t *g)
{
    enum MHD_Result result = MHD_NO;
    cJSON *body = web_body_object(req, &result);
    if (body == NULL) {
        return result;
    }
    static const char *const names[] = {"file", NULL};
    const cJSON *file = cJSON_GetObjectItemCaseSensitive(body, "file");
    if (!web_fields_known(req, body, names, &result)) {
        cJSON_Delete(body);
        return result;
    }
    if (file == NULL || (!cJSON_IsString(file) && !cJSON_IsNull(file))) {
        cJSON_Delete(body);
        return web_reply_error(req, MHD_HTTP_BAD_REQUEST, E_INVALID_PARAMETER,
                               "file: a /user/ file name or null");
    }
    char why[512];
    bool ok =
        gripper_set_startup(g, cJSON_IsString(file) ? file->valuestring : NULL, why, sizeof(why));
    cJSON_Delete(body);
    if (!ok) {
        return web_reply_error(req, MHD_HTTP_NOT_FOUND, E_NOT_FOUND, "%s", why);
    }
    return get_script(req, g);
}

static const char *script_method(const char *rest)
{
    if (rest[0] == '\0' || strcmp(rest, "/console") == 0) {
        return MHD_HTTP_METHOD_GET;
    }
    return strcmp(rest, "/startup") == 0 ? MHD_HTTP_METHOD_PUT : MHD_HTTP_METHOD_POST;
}

enum MHD_Result web_script_route(const web_request_t *req, gripper_t *g, const char *rest)
{
    const char *method = script_method(rest);
    if (strcmp(rest, "") != 0 && strcmp(rest, "/console") != 0 && strcmp(rest, "/run") != 0 &&
        strcmp(rest, "/stop") != 0 && strcmp(rest, "/startup") != 0) {
        return web_reply_error(req, MHD_HTTP_NOT_FOUND, E_NOT_FOUND, "no such path: %s", req->url);
    }
    if (!is_method(req, method)) {
        return web_reply_wrong_method(req, method);
    }
    if (rest[0] == '\0') {
        return get_script(req, g);
    }
    if (strcmp(rest, "/console") == 0) {
        return get_console(req, g);
    }
    if (!req->sim_allowed) {
        return forbidden(req);
    }
    if (strcmp(rest, "/startup") == 0) {
        return set_startup(req, g);
    }
    return strcmp(rest, "/run") == 0 ? run_script(req, g) : stop_script(req, g);
}

/* ---- the store ------------------------------------------------------------ */

static const char *store_of(const gripper_t *g)
{
    const char *dir = g->script != NULL ? script_store_dir(g->script) : "";
    return dir[0] != '\0' ? dir : NULL;
}

static bool store_writable(const gripper_t *g)
{
    return g->opts->script_dir != NULL; /* else: the --script file's directory */
}

static enum MHD_Result list_files(const web_request_t *req, const char *dir, bool writable)
{
    DIR *d = opendir(dir);
    if (d == NULL) {
        return web_reply_error(req, MHD_HTTP_INTERNAL_SERVER_ERROR, E_IO_ERROR, "%s: %s", dir,
                               strerror(errno));
    }
    cJSON *j = cJSON_CreateObject();
    cJSON_AddBoolToObject(j, "writable", writable);
    cJSON *files = cJSON_AddArrayToObject(j, "files");
    struct dirent *e;
    while ((e = readdir(d)) != NULL) {
        char path[4096];
        struct stat st;
        if (!script_store_name_ok(e->d_name) ||
            (size_t)snprintf(path, sizeof(path), "%s/%s", dir, e->d_name) >= sizeof(path) ||
            stat(path, &st) != 0 || !S_ISREG(st.st_mode)) {
            continue;
        }
        cJSON *f = cJSON_CreateObject();
        cJSON_AddStringToObject(f, "name", e->d_name);
        cJSON_AddNumberToObject(f, "bytes", (double)st.st_size);
        cJSON_AddItemToArray(files, f);
    }
    closedir(d);
    return web_reply_json(req, MHD_HTTP_OK, j);
}

static unsigned count_files(const char *dir)
{
    DIR *d = opendir(dir);
    unsigned n = 0;
    struct dirent *e;
    while (d != NULL && (e = readdir(d)) != NULL) {
        n += script_store_name_ok(e->d_name) && e->d_type == DT_REG ? 1u : 0u;
    }
    if (d != NULL) {
        closedir(d);
    }
    return n;
}

static enum MHD_Result get_file(const web_request_t *req, const char *path)
{
    FILE *f = fopen(path, "rb");
    if (f == NULL) {
        return web_reply_error(req, MHD_HTTP_NOT_FOUND, E_NOT_FOUND, "no such file");
    }
    char *bytes = malloc(256u * 1024u);
    size_t len = bytes != NULL ? fread(bytes, 1, 256u * 1024u, f) : 0u;
    fclose(f);
    if (bytes == NULL) {
        return web_reply_error(req, MHD_HTTP_INTERNAL_SERVER_ERROR, E_INSUFFICIENT_RESOURCES,
                               "out of memory");
    }
    /* copied: web_reply_bytes() keeps a pointer to static assets */
    struct MHD_Response *response =
        MHD_create_response_from_buffer(len, bytes, MHD_RESPMEM_MUST_COPY);
    free(bytes);
    if (response == NULL) {
        return MHD_NO;
    }
    MHD_add_response_header(response, MHD_HTTP_HEADER_CONTENT_TYPE, "text/plain; charset=utf-8");
    enum MHD_Result result = MHD_queue_response(req->connection, MHD_HTTP_OK, response);
    MHD_destroy_response(response);
    return result;
}

static enum MHD_Result write_file(const web_request_t *req, const char *dir, const char *path,
                                  const char *text, size_t len)
{
    struct stat st;
    bool exists = stat(path, &st) == 0;
    if (!exists && count_files(dir) >= STORE_FILES_MAX) {
        return web_reply_error(req, MHD_HTTP_INSUFFICIENT_STORAGE, E_INSUFFICIENT_RESOURCES,
                               "the store holds %u files at most", STORE_FILES_MAX);
    }
    char temp[4200];
    snprintf(temp, sizeof(temp), "%s.part", path);
    FILE *f = fopen(temp, "wb");
    bool ok = f != NULL && fwrite(text, 1, len, f) == len;
    ok = f != NULL && fclose(f) == 0 && ok;
    if (!ok || rename(temp, path) != 0) {
        unlink(temp);
        return web_reply_error(req, MHD_HTTP_INTERNAL_SERVER_ERROR, E_WRITE_ERROR, "%s: %s", path,
                               strerror(errno));
    }
    cJSON *j = cJSON_CreateObject();
    cJSON_AddNumberToObject(j, "bytes", (double)len);
    return web_reply_json(req, exists ? MHD_HTTP_OK : MHD_HTTP_CREATED, j);
}

/* The body {"text": "..."}: every changing request is JSON (docs/web.md's
 * cross-site rule). Written beside the file, then renamed: a reader never
 * sees half a file. */
static enum MHD_Result put_file(const web_request_t *req, const char *dir, const char *path)
{
    enum MHD_Result result = MHD_NO;
    cJSON *body = web_body_object(req, &result);
    if (body == NULL) {
        return result;
    }
    static const char *const names[] = {"text", NULL};
    const char *text = NULL;
    bool given = false;
    if (!web_fields_known(req, body, names, &result) ||
        !web_field_string(req, body, "text", &text, &given, &result)) {
        cJSON_Delete(body);
        return result;
    }
    if (!given) {
        cJSON_Delete(body);
        return web_reply_error(req, MHD_HTTP_BAD_REQUEST, E_NOT_ENOUGH_PARAMS,
                               "text: the file's contents are missing");
    }
    result = write_file(req, dir, path, text, strlen(text));
    cJSON_Delete(body);
    return result;
}

static enum MHD_Result delete_file(const web_request_t *req, const char *path)
{
    if (unlink(path) != 0) {
        return web_reply_error(req, MHD_HTTP_NOT_FOUND, E_NOT_FOUND, "no such file");
    }
    return web_reply_json(req, MHD_HTTP_OK, cJSON_CreateObject());
}

static enum MHD_Result file_route(const web_request_t *req, const gripper_t *g, const char *dir,
                                  const char *name)
{
    if (!script_store_name_ok(name)) {
        return web_reply_error(req, MHD_HTTP_BAD_REQUEST, E_INVALID_PARAMETER,
                               "not a store file name");
    }
    char path[4096];
    snprintf(path, sizeof(path), "%s/%s", dir, name);
    if (is_method(req, MHD_HTTP_METHOD_GET)) {
        return get_file(req, path);
    }
    if (!is_method(req, MHD_HTTP_METHOD_PUT) && !is_method(req, MHD_HTTP_METHOD_DELETE)) {
        return web_reply_wrong_method(req, "GET, PUT, DELETE");
    }
    if (!req->sim_allowed) {
        return forbidden(req);
    }
    if (!store_writable(g)) {
        return web_reply_error(req, MHD_HTTP_FORBIDDEN, E_ACCESS_DENIED,
                               "the store is read-only (no --script-dir)");
    }
    return is_method(req, MHD_HTTP_METHOD_PUT) ? put_file(req, dir, path) : delete_file(req, path);
}

enum MHD_Result web_files_route(const web_request_t *req, gripper_t *g, const char *rest)
{
    const char *dir = store_of(g);
    if (dir == NULL) {
        return web_reply_error(req, MHD_HTTP_NOT_FOUND, E_NOT_FOUND,
                               "no script store (--script-dir)");
    }
    if (rest[0] == '\0') {
        if (!is_method(req, MHD_HTTP_METHOD_GET)) {
            return web_reply_wrong_method(req, MHD_HTTP_METHOD_GET);
        }
        return list_files(req, dir, store_writable(g));
    }
    if (rest[0] != '/' || rest[1] == '\0') {
        return web_reply_error(req, MHD_HTTP_NOT_FOUND, E_NOT_FOUND, "no such path: %s", req->url);
    }
    return file_route(req, g, dir, rest + 1);
}
