/* SPDX-License-Identifier: BSD-3-Clause */
/* The /user/ store's routes (docs/web.md, docs/scripting.md): list, read,
 * write, delete, and the check every store name of the web passes (Run and
 * the startup choice too). The web reaches the store's Lua files and nothing
 * else: a name is NAME.lua, never one of wsgsim's own files (the --config,
 * --save-file, --log-file ... files, even one kept in the store under a .lua
 * name), and nothing but a regular file is opened, always without blocking
 * (a FIFO would hold the event loop until a writer came). Changing files
 * follows the simulation panel's rule (loopback clients only unless
 * --sim-bind names another address). */
#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "fleet.h"
#include "script.h"
#include "web/web_internal.h"

#define STORE_FILES_MAX 64u

static bool is_method(const web_request_t *req, const char *method)
{
    return strcmp(req->method, method) == 0;
}

static const char *store_of(const gripper_t *g)
{
    const char *dir = g->script != NULL ? script_store_dir(g->script) : "";
    return dir[0] != '\0' ? dir : NULL;
}

static bool store_writable(const gripper_t *g)
{
    return g->opts->script_dir != NULL; /* else: the --script file's directory */
}

/* Where a path names a file, whether or not it exists: its directory's real
 * path and its last name. */
static bool canonical(const char *path, char *out, size_t cap)
{
    const char *slash = strrchr(path, '/');
    char dir[PATH_MAX];
    char real[PATH_MAX];
    if (slash == NULL) {
        snprintf(dir, sizeof(dir), ".");
    } else {
        snprintf(dir, sizeof(dir), "%.*s", slash == path ? 1 : (int)(slash - path), path);
    }
    return realpath(dir, real) != NULL &&
           (size_t)snprintf(out, cap, "%s/%s", real, slash != NULL ? slash + 1 : path) < cap;
}

/* One file under two paths: the same inode (a link, a symlink), or the same
 * place for a file not written yet. */
static bool same_file(const char *a, const char *b)
{
    struct stat sa;
    struct stat sb;
    if (stat(a, &sa) == 0 && stat(b, &sb) == 0) {
        return sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
    }
    char ca[PATH_MAX];
    char cb[PATH_MAX];
    return canonical(a, ca, sizeof(ca)) && canonical(b, cb, sizeof(cb)) && strcmp(ca, cb) == 0;
}

/* A file wsgsim reads or writes for itself (the command line's files). */
static bool own_file(const gripper_t *g, const char *path)
{
    const host_options_t *o = g->opts;
    const char *const own[] = {o->config_path, o->save_path,     o->log_file,   o->scenario_path,
                               o->record_path, o->coverage_path, o->ready_file, o->can_log};
    for (size_t i = 0; i < sizeof(own) / sizeof(own[0]); i++) {
        if (own[i] != NULL && same_file(path, own[i])) {
            return true;
        }
    }
    return false;
}

const char *web_store_path(const gripper_t *g, const char *name, char *path, size_t cap)
{
    const char *dir = store_of(g);
    const char *plain = strncmp(name, "/user/", 6) == 0 ? name + 6 : name;
    if (dir == NULL) {
        return "the device has no /user/ store (--script-dir)";
    }
    if (!script_store_name_ok(plain) || (size_t)snprintf(path, cap, "%s/%s", dir, plain) >= cap) {
        return "not a store file name (NAME.lua: printable ASCII, no '/', no '..')";
    }
    if (own_file(g, path)) {
        return "one of wsgsim's own files (--config, --save-file, --log-file ...), not a script";
    }
    return NULL;
}

const char *web_store_reason(const char *why, const char *path)
{
    size_t len = strlen(path);
    return strncmp(why, path, len) == 0 && strncmp(why + len, ": ", 2) == 0 ? why + len + 2 : why;
}

const char *web_store_check_file(const gripper_t *g, const char *name, char *path, size_t cap)
{
    const char *refused = web_store_path(g, name, path, cap);
    struct stat st;
    if (refused != NULL) {
        return refused;
    }
    if (stat(path, &st) != 0) {
        return "no such file in the /user/ store";
    }
    return S_ISREG(st.st_mode) ? NULL : "not a regular file";
}

static bool listed(const gripper_t *g, const char *dir, const char *name, struct stat *st)
{
    char path[PATH_MAX];
    return script_store_name_ok(name) &&
           (size_t)snprintf(path, sizeof(path), "%s/%s", dir, name) < sizeof(path) &&
           stat(path, st) == 0 && S_ISREG(st->st_mode) && !own_file(g, path);
}

static enum MHD_Result list_files(const web_request_t *req, const gripper_t *g, const char *dir)
{
    DIR *d = opendir(dir);
    if (d == NULL) {
        return web_reply_error(req, MHD_HTTP_INTERNAL_SERVER_ERROR, E_IO_ERROR,
                               "the store cannot be read: %s", strerror(errno));
    }
    cJSON *j = cJSON_CreateObject();
    cJSON_AddBoolToObject(j, "writable", store_writable(g));
    cJSON *files = cJSON_AddArrayToObject(j, "files");
    struct dirent *e;
    while ((e = readdir(d)) != NULL) {
        struct stat st;
        if (!listed(g, dir, e->d_name, &st)) {
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
    char why[PATH_MAX + 64];
    size_t len = 0;
    char *bytes = script_read_file(path, &len, why, sizeof(why));
    if (bytes == NULL) {
        return web_reply_error(req, MHD_HTTP_NOT_FOUND, E_NOT_FOUND, "%s",
                               web_store_reason(why, path));
    }
    struct MHD_Response *response =
        MHD_create_response_from_buffer(len, bytes, MHD_RESPMEM_MUST_FREE);
    if (response == NULL) {
        free(bytes);
        return MHD_NO;
    }
    MHD_add_response_header(response, MHD_HTTP_HEADER_CONTENT_TYPE, "text/plain; charset=utf-8");
    enum MHD_Result result = MHD_queue_response(req->connection, MHD_HTTP_OK, response);
    MHD_destroy_response(response);
    return result;
}

/* The text into a new file beside the target (whatever had that name is
 * removed first: O_EXCL never opens a FIFO or follows a link), then renamed
 * over it: a reader never sees half a file. */
static bool write_beside(const char *path, const char *text, size_t len)
{
    char temp[PATH_MAX + 8];
    if ((size_t)snprintf(temp, sizeof(temp), "%s.part", path) >= sizeof(temp)) {
        errno = ENAMETOOLONG;
        return false;
    }
    (void)unlink(temp);
    int fd = open(temp, O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC, 0644);
    if (fd < 0) {
        return false;
    }
    bool ok = write(fd, text, len) == (ssize_t)len;
    ok = close(fd) == 0 && ok;
    if (!ok || rename(temp, path) != 0) {
        int saved = errno;
        unlink(temp);
        errno = saved;
        return false;
    }
    return true;
}

static enum MHD_Result write_file(const web_request_t *req, const char *dir, const char *path,
                                  const char *text)
{
    struct stat st;
    bool exists = lstat(path, &st) == 0;
    size_t len = strlen(text);
    if (!exists && count_files(dir) >= STORE_FILES_MAX) {
        return web_reply_error(req, MHD_HTTP_INSUFFICIENT_STORAGE, E_INSUFFICIENT_RESOURCES,
                               "the store holds %u files at most", STORE_FILES_MAX);
    }
    if (!write_beside(path, text, len)) {
        return web_reply_error(req, MHD_HTTP_INTERNAL_SERVER_ERROR, E_WRITE_ERROR,
                               "the file cannot be written: %s", strerror(errno));
    }
    cJSON *j = cJSON_CreateObject();
    cJSON_AddNumberToObject(j, "bytes", (double)len);
    return web_reply_json(req, exists ? MHD_HTTP_OK : MHD_HTTP_CREATED, j);
}

/* The body {"text": "..."}: every changing request is JSON (docs/web.md's
 * cross-site rule). */
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
    result = write_file(req, dir, path, text);
    cJSON_Delete(body);
    return result;
}

/* The file at path is the startup script device g runs at its next
 * power-on (a store name, or the host path --script gave). */
static bool runs_at_power_on(const gripper_t *g, const char *path)
{
    const char *startup = g->opts->script;
    char its[PATH_MAX];
    if (startup == NULL || !g->opts->script_autostart) {
        return false;
    }
    if (web_store_path(g, startup, its, sizeof(its)) != NULL) {
        snprintf(its, sizeof(its), "%s", startup);
    }
    return same_file(path, its);
}

/* The startup script of a device (any of the fleet: they share the store)
 * is not deleted: the user chooses another or none first, so what the
 * device runs at power-on never changes behind the page's back. */
static enum MHD_Result delete_file(const web_request_t *req, const char *path, const char *name)
{
    struct stat st;
    if (lstat(path, &st) != 0) {
        return web_reply_error(req, MHD_HTTP_NOT_FOUND, E_NOT_FOUND, "no such file");
    }
    for (unsigned i = 0; i < fleet_count(req->app->fleet); i++) {
        if (runs_at_power_on(fleet_gripper(req->app->fleet, i), path)) {
            return web_reply_error(req, MHD_HTTP_CONFLICT, E_NOT_AVAILABLE,
                                   "%.100s is device %u's startup script: choose another "
                                   "startup script or none first",
                                   name, i);
        }
    }
    if (unlink(path) != 0) {
        return web_reply_error(req, MHD_HTTP_NOT_FOUND, E_NOT_FOUND, "no such file");
    }
    return web_reply_json(req, MHD_HTTP_OK, cJSON_CreateObject());
}

static enum MHD_Result file_route(const web_request_t *req, const gripper_t *g, const char *dir,
                                  const char *name)
{
    char path[PATH_MAX];
    const char *refused = web_store_path(g, name, path, sizeof(path));
    if (refused != NULL) {
        return web_reply_error(req, MHD_HTTP_BAD_REQUEST, E_INVALID_PARAMETER, "%s", refused);
    }
    if (is_method(req, MHD_HTTP_METHOD_GET)) {
        return get_file(req, path);
    }
    if (!is_method(req, MHD_HTTP_METHOD_PUT) && !is_method(req, MHD_HTTP_METHOD_DELETE)) {
        return web_reply_wrong_method(req, "GET, PUT, DELETE");
    }
    if (!req->sim_allowed) {
        return web_reply_error(req, MHD_HTTP_FORBIDDEN, E_ACCESS_DENIED,
                               "scripts are run and stored for loopback clients only "
                               "(--sim-bind allows more)");
    }
    if (!store_writable(g)) {
        return web_reply_error(req, MHD_HTTP_FORBIDDEN, E_ACCESS_DENIED,
                               "the store is read-only (no --script-dir)");
    }
    return is_method(req, MHD_HTTP_METHOD_PUT) ? put_file(req, dir, path)
                                               : delete_file(req, path, name);
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
        return list_files(req, g, dir);
    }
    if (rest[0] != '/' || rest[1] == '\0') {
        return web_reply_error(req, MHD_HTTP_NOT_FOUND, E_NOT_FOUND, "no such path: %s", req->url);
    }
    return file_route(req, g, dir, rest + 1);
}
