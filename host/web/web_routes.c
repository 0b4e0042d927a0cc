/* SPDX-License-Identifier: BSD-3-Clause */
#include "web/web_routes.h"

#include <stdlib.h>
#include <string.h>

#include "fleet.h"
#include "web/web_json.h"
#include "web/web_lines.h"

#define API_DEVICES "/api/devices"
#define ID_DIGITS_MAX 6

static bool is_method(const web_request_t *req, const char *method)
{
    return strcmp(req->method, method) == 0;
}

static enum MHD_Result not_found(const web_request_t *req)
{
    return web_reply_error(req, MHD_HTTP_NOT_FOUND, E_NOT_FOUND, "no such path: %s", req->url);
}

static cJSON *device_entry(fleet_t *fleet, unsigned i)
{
    gripper_t *g = fleet_gripper(fleet, i);
    const wsg_config_t *cfg = wsg_device_snapshot(&g->device)->config;
    cJSON *j = cJSON_CreateObject();
    cJSON_AddNumberToObject(j, "id", i);
    cJSON_AddStringToObject(j, "model", cfg->devtype);
    cJSON_AddNumberToObject(j, "serial", cfg->serial);
    cJSON_AddStringToObject(j, "tag", cfg->tag);
    char address[64];
    fleet_device_address(fleet, i, address, sizeof(address));
    cJSON_AddStringToObject(j, "address", address);
    cJSON_AddNumberToObject(j, "tcp_port", fleet_tcp_port(fleet, i));
    cJSON_AddNumberToObject(j, "udp_port", fleet_udp_port(fleet, i));
    return j;
}

static enum MHD_Result list_devices(const web_request_t *req)
{
    if (!is_method(req, MHD_HTTP_METHOD_GET)) {
        return web_reply_wrong_method(req, MHD_HTTP_METHOD_GET);
    }
    cJSON *root = cJSON_CreateObject();
    cJSON_AddBoolToObject(root, "sim_allowed", req->sim_allowed); /* may this client? */
    cJSON *list = cJSON_AddArrayToObject(root, "devices");
    for (unsigned i = 0; i < fleet_count(req->app->fleet); i++) {
        cJSON_AddItemToArray(list, device_entry(req->app->fleet, i));
    }
    return web_reply_json(req, MHD_HTTP_OK, root);
}

static enum MHD_Result get_state(const web_request_t *req, gripper_t *g)
{
    if (!is_method(req, MHD_HTTP_METHOD_GET)) {
        return web_reply_wrong_method(req, MHD_HTTP_METHOD_GET);
    }
    web_lines_watch(&req->app->lines);
    web_json_t j;
    web_json_init(&j);
    web_state_write(req->app, &j, g);
    return web_reply_json_text(req, MHD_HTTP_OK, web_json_take(&j, NULL));
}

static enum MHD_Result get_events(const web_request_t *req, gripper_t *g)
{
    if (!is_method(req, MHD_HTTP_METHOD_GET)) {
        return web_reply_wrong_method(req, MHD_HTTP_METHOD_GET);
    }
    return web_events_route(req, g);
}

static enum MHD_Result post_only(const web_request_t *req, gripper_t *g, const char *name,
                                 enum MHD_Result (*route)(const web_request_t *, gripper_t *,
                                                          const char *))
{
    if (!is_method(req, MHD_HTTP_METHOD_POST)) {
        return web_reply_wrong_method(req, MHD_HTTP_METHOD_POST);
    }
    return route(req, g, name);
}

/* The part after /api/devices/{id}/. */
static enum MHD_Result device_route(const web_request_t *req, gripper_t *g, const char *rest)
{
    if (strcmp(rest, "state") == 0) {
        return get_state(req, g);
    }
    if (strcmp(rest, "events") == 0) {
        return get_events(req, g);
    }
    if (strcmp(rest, "system") == 0) {
        return web_system_route(req, g);
    }
    if (strncmp(rest, "settings", 8) == 0 && (rest[8] == '\0' || rest[8] == '/')) {
        return web_settings_route(req, g, rest + 8);
    }
    if (strncmp(rest, "script", 6) == 0 && (rest[6] == '\0' || rest[6] == '/')) {
        return web_script_route(req, g, rest + 6);
    }
    if (strncmp(rest, "files", 5) == 0 && (rest[5] == '\0' || rest[5] == '/')) {
        return web_files_route(req, g, rest + 5);
    }
    if (strncmp(rest, "ops/", 4) == 0 && rest[4] != '\0') {
        return post_only(req, g, rest + 4, web_ops_route);
    }
    if (strncmp(rest, "sim/", 4) == 0 && rest[4] != '\0') {
        if (!req->sim_allowed) {
            return web_reply_error(req, MHD_HTTP_FORBIDDEN, E_ACCESS_DENIED,
                                   "the simulation is served to loopback clients only "
                                   "(--sim-bind allows more)");
        }
        return post_only(req, g, rest + 4, web_sim_route);
    }
    return not_found(req);
}

/* "{id}" or "{id}/..." after /api/devices/: the device, its number of
 * characters, or NULL for no such device. */
static gripper_t *parse_device(fleet_t *fleet, const char *text, size_t *used)
{
    size_t digits = strspn(text, "0123456789");
    if (digits == 0 || digits > ID_DIGITS_MAX || (text[digits] != '\0' && text[digits] != '/')) {
        return NULL;
    }
    unsigned long id = strtoul(text, NULL, 10);
    *used = digits;
    return id < fleet_count(fleet) ? fleet_gripper(fleet, (unsigned)id) : NULL;
}

static enum MHD_Result api_route(const web_request_t *req, const char *rest)
{
    if (rest[0] == '\0') {
        return list_devices(req);
    }
    size_t used = 0;
    gripper_t *g = rest[0] == '/' ? parse_device(req->app->fleet, rest + 1, &used) : NULL;
    if (g == NULL) {
        return rest[0] == '/' && strspn(rest + 1, "0123456789") > 0
                   ? web_reply_error(req, MHD_HTTP_NOT_FOUND, E_NOT_FOUND, "no such device")
                   : not_found(req);
    }
    const char *after = rest + 1 + used;
    if (after[0] != '/') {
        return not_found(req);
    }
    return device_route(req, g, after + 1);
}

void web_app_init(web_app_t *app, struct fleet *fleet)
{
    memset(app, 0, sizeof(*app));
    app->fleet = fleet;
    web_static_init(app->system_files);
}

void web_app_release(web_app_t *app)
{
    web_ops_forget(&app->ops);
    web_lines_disable(&app->lines);
    web_static_release(app->system_files);
}

enum MHD_Result web_routes_dispatch(const web_request_t *req)
{
    if (strncmp(req->url, API_DEVICES, strlen(API_DEVICES)) == 0) {
        return api_route(req, req->url + strlen(API_DEVICES));
    }
    enum MHD_Result result = MHD_NO;
    if (web_static_route(req, &result)) {
        return result;
    }
    return not_found(req);
}
