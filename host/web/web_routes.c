/* SPDX-License-Identifier: BSD-3-Clause */
#include "web/web_routes.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fleet.h"
#include "state_json.h"
#include "json_writer.h"
#include "web/web_lines.h"

#define API_DEVICES "/api/devices"
#define ID_DIGITS_MAX 6

/* A route's handler: g the device of its path ({id}; NULL without one),
 * rest what its pattern's "*" matched ("" without one). */
typedef enum MHD_Result (*web_handler_t)(const web_request_t *req, gripper_t *g, const char *rest);

/* How a pattern's end matches: the path ends with it, or goes on with one
 * or more characters (`*`: the name of an operation), or with nothing or
 * "/..." (`tree`: a subtree whose handler reads the rest). */
typedef enum { MATCH_EXACT, MATCH_STAR, MATCH_TREE } match_t;

typedef struct {
    const char *method; /* NULL: every method, the handler answers the others */
    const char *pattern;
    match_t match;
    web_handler_t handler;
    bool sim; /* the simulation's: loopback peers only (as the control channel) */
} web_route_t;

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

static enum MHD_Result list_devices(const web_request_t *req, gripper_t *g, const char *rest)
{
    (void)g;
    (void)rest;
    cJSON *root = cJSON_CreateObject();
    cJSON_AddBoolToObject(root, "sim_allowed", req->sim_allowed); /* may this client? */
    cJSON *list = cJSON_AddArrayToObject(root, "devices");
    for (unsigned i = 0; i < fleet_count(req->app->fleet); i++) {
        cJSON_AddItemToArray(list, device_entry(req->app->fleet, i));
    }
    return web_reply_json(req, MHD_HTTP_OK, root);
}

static enum MHD_Result get_state(const web_request_t *req, gripper_t *g, const char *rest)
{
    (void)rest;
    web_lines_watch(&req->app->lines);
    json_writer_t j;
    json_writer_init(&j);
    web_state_write(req->app, &j, g);
    return web_reply_json_text(req, MHD_HTTP_OK, json_writer_take(&j, NULL));
}

static enum MHD_Result get_events(const web_request_t *req, gripper_t *g, const char *rest)
{
    (void)rest;
    return web_events_route(req, g);
}

static enum MHD_Result get_system(const web_request_t *req, gripper_t *g, const char *rest)
{
    (void)rest;
    return web_system_route(req, g);
}

#define DEVICE API_DEVICES "/{id}/"

/* Every path of the API, in the order they are tried. */
static const web_route_t routes[] = {
    {"GET", API_DEVICES, MATCH_EXACT, list_devices, false},
    {"GET", DEVICE "state", MATCH_EXACT, get_state, false},
    {"GET", DEVICE "events", MATCH_EXACT, get_events, false},
    {"GET", DEVICE "system", MATCH_EXACT, get_system, false},
    {"GET", DEVICE "scene", MATCH_EXACT, web_scene_route, false},
    {"GET", DEVICE "settings", MATCH_EXACT, web_settings_get, false},
    {"PUT", DEVICE "settings", MATCH_EXACT, web_settings_put, false},
    {"POST", DEVICE "settings/save", MATCH_EXACT, web_settings_save, false},
    {"GET", DEVICE "script", MATCH_EXACT, web_script_get, false},
    {"GET", DEVICE "script/console", MATCH_EXACT, web_script_console, false},
    {"POST", DEVICE "script/run", MATCH_EXACT, web_script_run, false},
    {"POST", DEVICE "script/stop", MATCH_EXACT, web_script_stop, false},
    {"PUT", DEVICE "script/startup", MATCH_EXACT, web_script_startup, false},
    {NULL, DEVICE "files", MATCH_TREE, web_files_route, false},
    {"POST", DEVICE "ops/", MATCH_STAR, web_ops_route, false},
    {"POST", DEVICE "sim/", MATCH_STAR, web_sim_route, true},
};
#define ROUTE_COUNT (sizeof(routes) / sizeof(routes[0]))

/* The device of "{id}" at the start of text ("/" or the end after it), its
 * digits in *used; NULL when there is none such. */
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

/* Whether path matches the route's pattern ("{id}" stands for the device
 * number, skipped here: the device is found before); *rest: what the end
 * matched. */
static bool matches(const web_route_t *route, const char *path, const char *id, size_t id_len,
                    const char **rest)
{
    const char *p = route->pattern;
    const char *id_at = strstr(p, "{id}");
    size_t head = id_at != NULL ? (size_t)(id_at - p) : strlen(p);
    if (strncmp(path, p, head) != 0) {
        return false;
    }
    path += head;
    if (id_at != NULL) {
        if (id == NULL || path != id) {
            return false;
        }
        path += id_len;
        p = id_at + strlen("{id}");
        size_t tail = strlen(p);
        if (strncmp(path, p, tail) != 0) {
            return false;
        }
        path += tail;
    }
    *rest = path;
    switch (route->match) {
    case MATCH_STAR:
        return path[0] != '\0';
    case MATCH_TREE:
        return path[0] == '\0' || path[0] == '/';
    case MATCH_EXACT:
    default:
        return path[0] == '\0';
    }
}

/* The methods the routes of path take, "GET, PUT", for a 405. */
static void allowed_methods(const bool *hit, char *out, size_t cap)
{
    out[0] = '\0';
    for (size_t i = 0; i < ROUTE_COUNT; i++) {
        if (hit[i] && routes[i].method != NULL) {
            size_t len = strlen(out);
            snprintf(out + len, cap - len, "%s%s", len > 0 ? ", " : "", routes[i].method);
        }
    }
}

/* The route of path and method among those that match path, or a reply:
 * 403 for the simulation's to a peer it is not served to, 405 with the
 * methods path takes. */
static enum MHD_Result dispatch_api(const web_request_t *req, gripper_t *g, const char *id,
                                    size_t id_len)
{
    bool hit[ROUTE_COUNT] = {false};
    bool any = false;
    for (size_t i = 0; i < ROUTE_COUNT; i++) {
        const char *matched = "";
        hit[i] = matches(&routes[i], req->url, id, id_len, &matched);
        if (!hit[i]) {
            continue;
        }
        if (!any && routes[i].sim && !req->sim_allowed) {
            return web_reply_error(req, MHD_HTTP_FORBIDDEN, E_ACCESS_DENIED,
                                   "the simulation is served to loopback clients only "
                                   "(--sim-bind allows more)");
        }
        any = true;
        if (routes[i].method == NULL || strcmp(routes[i].method, req->method) == 0) {
            return routes[i].handler(req, g, matched);
        }
    }
    if (!any) {
        return not_found(req);
    }
    char allowed[64];
    allowed_methods(hit, allowed, sizeof(allowed));
    return web_reply_wrong_method(req, allowed);
}

/* /api/devices..., its device ({id}) found first: a number that names no
 * device is 404 "no such device" whatever follows. */
static enum MHD_Result api_route(const web_request_t *req, const char *rest)
{
    if (rest[0] != '/') {
        return rest[0] == '\0' ? dispatch_api(req, NULL, NULL, 0) : not_found(req);
    }
    size_t used = 0;
    gripper_t *g = parse_device(req->app->fleet, rest + 1, &used);
    if (g == NULL) {
        return strspn(rest + 1, "0123456789") > 0
                   ? web_reply_error(req, MHD_HTTP_NOT_FOUND, E_NOT_FOUND, "no such device")
                   : not_found(req);
    }
    return dispatch_api(req, g, rest + 1, used);
}

void web_app_init(web_app_t *app, struct fleet *fleet)
{
    memset(app, 0, sizeof(*app));
    app->fleet = fleet;
    app->sysflag_names = state_json_sysflag_names();
    web_static_init(app->system_files);
}

void web_app_release(web_app_t *app)
{
    web_ops_forget(&app->ops);
    web_lines_disable(&app->lines);
    web_static_release(app->system_files);
    free(app->sysflag_names);
    app->sysflag_names = NULL;
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
