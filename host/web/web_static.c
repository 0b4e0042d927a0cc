/* SPDX-License-Identifier: BSD-3-Clause */
/* The page: / goes to device 0's, /devices/{id} is index.html (the page
 * reads its id from the path), /static/NAME any other built-in file or one
 * of Debian's libjs-dygraphs and libjs-codemirror files. */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "fleet.h"
#include "log.h"
#include "web/web_assets.h"
#include "web/web_internal.h"

#define DEVICES_PREFIX "/devices/"
#define STATIC_PREFIX "/static/"

/* The chart library and the script editor are not built in: they are
 * served from where Debian's libjs-dygraphs and libjs-codemirror install
 * them (the wsgsim package depends on both), read on the first request and
 * kept until the server stops, so that the binary carries none of their
 * code. */
#define DYGRAPHS_DIR "/usr/share/javascript/dygraphs/"
#define CODEMIRROR_DIR "/usr/share/javascript/codemirror/"
#define SYSTEM_FILE_MAX (8u << 20) /* codemirror.js, the largest, is about 400 KiB */
#define JS_TYPE "text/javascript; charset=utf-8"
#define CSS_TYPE "text/css; charset=utf-8"

typedef web_system_file_t system_file_t;

static const system_file_t system_file_names[WEB_SYSTEM_FILE_COUNT] = {
    {"dygraph.min.js", DYGRAPHS_DIR "dygraph.min.js", "libjs-dygraphs", JS_TYPE, NULL, 0},
    {"dygraph.min.css", DYGRAPHS_DIR "dygraph.min.css", "libjs-dygraphs", CSS_TYPE, NULL, 0},
    {"codemirror.js", CODEMIRROR_DIR "lib/codemirror.js", "libjs-codemirror", JS_TYPE, NULL, 0},
    {"codemirror.css", CODEMIRROR_DIR "lib/codemirror.css", "libjs-codemirror", CSS_TYPE, NULL, 0},
    {"codemirror-lua.js", CODEMIRROR_DIR "mode/lua/lua.js", "libjs-codemirror", JS_TYPE, NULL, 0},
    {"codemirror-matchbrackets.js", CODEMIRROR_DIR "addon/edit/matchbrackets.js",
     "libjs-codemirror", JS_TYPE, NULL, 0},
};

void web_static_init(web_system_file_t *files)
{
    memcpy(files, system_file_names, sizeof(system_file_names));
}

void web_static_release(web_system_file_t *files)
{
    for (unsigned i = 0; i < WEB_SYSTEM_FILE_COUNT; i++) {
        free(files[i].bytes);
    }
    web_static_init(files);
}

static const web_asset_t *find_asset(const char *name)
{
    for (const web_asset_t *a = web_assets; a->name != NULL; a++) {
        if (strcmp(a->name, name) == 0) {
            return a;
        }
    }
    return NULL;
}

/* "/devices/{id}" with an existing device id. */
static bool is_device_page(fleet_t *fleet, const char *url)
{
    if (strncmp(url, DEVICES_PREFIX, strlen(DEVICES_PREFIX)) != 0) {
        return false;
    }
    const char *id = url + strlen(DEVICES_PREFIX);
    size_t digits = strspn(id, "0123456789");
    return digits > 0 && digits <= 6 && id[digits] == '\0' &&
           strtoul(id, NULL, 10) < fleet_count(fleet);
}

static bool is_read(const web_request_t *req)
{
    return strcmp(req->method, MHD_HTTP_METHOD_GET) == 0 ||
           strcmp(req->method, MHD_HTTP_METHOD_HEAD) == 0;
}

static enum MHD_Result serve(const web_request_t *req, const web_asset_t *asset)
{
    if (!is_read(req)) {
        return web_reply_wrong_method(req, MHD_HTTP_METHOD_GET);
    }
    return web_reply_bytes(req, MHD_HTTP_OK, asset->content_type, asset->bytes, asset->len);
}

static system_file_t *find_system_file(system_file_t *files, const char *name)
{
    for (unsigned i = 0; i < WEB_SYSTEM_FILE_COUNT; i++) {
        if (strcmp(files[i].name, name) == 0) {
            return &files[i];
        }
    }
    return NULL;
}

/* Reads path whole into f; false with errno set. */
static bool read_whole(const char *path, system_file_t *f)
{
    FILE *in = fopen(path, "rb");
    struct stat st;
    if (in == NULL) {
        return false;
    }
    bool ok = fstat(fileno(in), &st) == 0;
    if (ok && (!S_ISREG(st.st_mode) || (size_t)st.st_size > SYSTEM_FILE_MAX)) {
        errno = EFBIG;
        ok = false;
    }
    errno = ok ? 0 : errno;
    unsigned char *bytes = ok ? malloc((size_t)st.st_size + 1u) : NULL;
    size_t len = bytes != NULL ? fread(bytes, 1, (size_t)st.st_size, in) : 0;
    ok = bytes != NULL && len == (size_t)st.st_size && ferror(in) == 0;
    int read_errno = errno;
    fclose(in);
    if (!ok) {
        free(bytes);
        errno = read_errno != 0 ? read_errno : EIO;
        return false;
    }
    f->bytes = bytes;
    f->len = len;
    return true;
}

static enum MHD_Result serve_system_file(const web_request_t *req, system_file_t *f)
{
    if (!is_read(req)) {
        return web_reply_wrong_method(req, MHD_HTTP_METHOD_GET);
    }
    if (f->bytes == NULL && !read_whole(f->path, f)) {
        const char *why = strerror(errno);
        host_logf(HAL_LOG_WARN, "http: cannot read %s: %s (install %s)", f->path, why, f->package);
        return web_reply_error(req, MHD_HTTP_NOT_FOUND, E_NOT_AVAILABLE,
                               "cannot read %s: %s (install %s)", f->path, why, f->package);
    }
    web_asset_t asset = {f->name, f->content_type, f->bytes, f->len};
    return serve(req, &asset);
}

bool web_static_route(const web_request_t *req, enum MHD_Result *result)
{
    const web_asset_t *asset = NULL;
    if (strcmp(req->url, "/") == 0) {
        *result = web_reply_redirect(req, "/devices/0");
        return true;
    }
    if (is_device_page(req->app->fleet, req->url)) {
        asset = find_asset("index.html");
    } else if (strncmp(req->url, STATIC_PREFIX, strlen(STATIC_PREFIX)) == 0) {
        const char *name = req->url + strlen(STATIC_PREFIX);
        system_file_t *file = find_system_file(req->app->system_files, name);
        if (file != NULL) {
            *result = serve_system_file(req, file);
            return true;
        }
        asset = find_asset(name);
    }
    if (asset == NULL) {
        return false;
    }
    *result = serve(req, asset);
    return true;
}
