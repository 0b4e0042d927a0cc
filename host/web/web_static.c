/* SPDX-License-Identifier: BSD-3-Clause */
/* The page: / goes to device 0's, /devices/{id} is index.html (the page
 * reads its id from the path), /static/NAME any other built-in file. */
#include <stdlib.h>
#include <string.h>

#include "fleet.h"
#include "web/web_assets.h"
#include "web/web_internal.h"

#define DEVICES_PREFIX "/devices/"
#define STATIC_PREFIX "/static/"

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
static bool is_device_page(const char *url)
{
    if (strncmp(url, DEVICES_PREFIX, strlen(DEVICES_PREFIX)) != 0) {
        return false;
    }
    const char *id = url + strlen(DEVICES_PREFIX);
    size_t digits = strspn(id, "0123456789");
    return digits > 0 && digits <= 6 && id[digits] == '\0' && strtoul(id, NULL, 10) < fleet_count();
}

static enum MHD_Result serve(const web_request_t *req, const web_asset_t *asset)
{
    if (strcmp(req->method, MHD_HTTP_METHOD_GET) != 0 &&
        strcmp(req->method, MHD_HTTP_METHOD_HEAD) != 0) {
        return web_reply_wrong_method(req, MHD_HTTP_METHOD_GET);
    }
    return web_reply_bytes(req, MHD_HTTP_OK, asset->content_type, asset->bytes, asset->len);
}

bool web_static_route(const web_request_t *req, enum MHD_Result *result)
{
    const web_asset_t *asset = NULL;
    if (strcmp(req->url, "/") == 0) {
        *result = web_reply_redirect(req, "/devices/0");
        return true;
    }
    if (is_device_page(req->url)) {
        asset = find_asset("index.html");
    } else if (strncmp(req->url, STATIC_PREFIX, strlen(STATIC_PREFIX)) == 0) {
        asset = find_asset(req->url + strlen(STATIC_PREFIX));
    }
    if (asset == NULL) {
        return false;
    }
    *result = serve(req, asset);
    return true;
}
