/* SPDX-License-Identifier: BSD-3-Clause */
/* What the web server's modules share: the request a route handles and the
 * replies it sends (docs/web.md). Only host/web/ includes it. */
#ifndef HOST_WEB_INTERNAL_H
#define HOST_WEB_INTERNAL_H

#include <stdbool.h>
#include <stddef.h>

#include <cjson/cJSON.h>
#include <microhttpd.h>

#include "gripper.h"
#include "simctl/control.h"
#include "web/web_events.h"
#include "web/web_lines.h"
#include "wsg/wsg_status.h"

/* A request body larger than this is refused with 413. */
#define WEB_BODY_MAX 4096u

/* web_ops.c: each device's web owner, allocated at the first operation. */
typedef struct web_owner web_owner_t;
typedef struct {
    web_owner_t *owners; /* one per device, NULL until the first op */
    unsigned count;
} web_ops_t;

/* web_static.c: a file of a Debian package the page uses (libjs-dygraphs,
 * libjs-codemirror), read at its first request and kept until the server
 * stops. */
typedef struct {
    const char *name;    /* under /static/ */
    const char *path;    /* where the package installs it */
    const char *package; /* what to install when it cannot be read */
    const char *content_type;
    unsigned char *bytes; /* NULL: not read yet */
    size_t len;
} web_system_file_t;
#define WEB_SYSTEM_FILE_COUNT 6u

/* What the routes of one web server keep between requests: its event
 * streams, the connection lines, the devices' web owners and the chart
 * library. Embedded in the server (web_server.c); the fuzz target of the
 * routes has one of its own. */
typedef struct web_app {
    struct fleet *fleet; /* the devices it serves */
    simctl_t *sim;       /* the simulated clock the state shows; NULL: none */
    web_events_t events;
    web_lines_t lines;
    web_ops_t ops;
    web_system_file_t system_files[WEB_SYSTEM_FILE_COUNT];
    char *sysflag_names; /* every state's "names", rendered once (NULL: each time) */
} web_app_t;

/* web_routes.c: serving fleet's devices, nothing kept yet, the lines off. */
void web_app_init(web_app_t *app, struct fleet *fleet);
/* Detaches the web's owners from their devices, frees the lines and the
 * files read (shutdown, while the devices exist). */
void web_app_release(web_app_t *app);

typedef struct {
    web_app_t *app; /* the server's routes that answer it */
    struct MHD_Connection *connection;
    const char *method;
    const char *url;
    const char *body; /* NUL-terminated; "" when none */
    size_t body_len;
    bool sim_allowed; /* the peer may use the simulation routes */
    simctl_t *sim;    /* runs them */
} web_request_t;

/* A JSON reply: takes ownership of json. */
enum MHD_Result web_reply_json(const web_request_t *req, unsigned http_status, cJSON *json);
/* {"error": <Appendix A name>, "code": n, "message": "..."} with this HTTP status. */
enum MHD_Result web_reply_error(const web_request_t *req, unsigned http_status, wsg_status_t status,
                                const char *fmt, ...) __attribute__((format(printf, 4, 5)));
enum MHD_Result web_reply_bytes(const web_request_t *req, unsigned http_status,
                                const char *content_type, const void *bytes, size_t len);
enum MHD_Result web_reply_redirect(const web_request_t *req, const char *location);
/* 405 naming the allowed method. */
enum MHD_Result web_reply_wrong_method(const web_request_t *req, const char *allowed);

/* The request's body as a JSON object; an empty body is {}. NULL after a
 * 400 reply was queued (*result holds what to return). */
cJSON *web_body_object(const web_request_t *req, enum MHD_Result *result);
/* Field checks for a body object: each returns false after queuing a 400
 * (wrong type) or, for required ones, a 400 naming the missing field. */
bool web_field_number(const web_request_t *req, const cJSON *body, const char *name, bool required,
                      double *out, bool *given, enum MHD_Result *result);
bool web_field_bool(const web_request_t *req, const cJSON *body, const char *name, bool *out,
                    bool *given, enum MHD_Result *result);
bool web_field_string(const web_request_t *req, const cJSON *body, const char *name,
                      const char **out, bool *given, enum MHD_Result *result);
/* False after a 400 when the body has a field not in names (NULL-ended). */
bool web_fields_known(const web_request_t *req, const cJSON *body, const char *const *names,
                      enum MHD_Result *result);
/* ?since=N (the log's, the script console's): a line number, 0 without
 * it; false after a 400 for anything else (a sign, text, beyond 64 bits). */
bool web_since_argument(const web_request_t *req, uint64_t *since, enum MHD_Result *result);

/* Brings device g's world up to now and senses it (what a GCL command does
 * first), so an operation or a read acts on the newest state. */
void web_device_sense(gripper_t *g);

/* web_state.c: GET /api/devices/{id}/state, one JSON object written to j. */
struct json_writer;
void web_state_write(web_app_t *app, struct json_writer *j, gripper_t *g);
/* web_settings.c: GET and PUT /api/devices/{id}/settings, POST .../save
 * (rest: "", the route table's) */
enum MHD_Result web_settings_get(const web_request_t *req, gripper_t *g, const char *rest);
enum MHD_Result web_settings_put(const web_request_t *req, gripper_t *g, const char *rest);
enum MHD_Result web_settings_save(const web_request_t *req, gripper_t *g, const char *rest);
/* web_ops.c: POST /api/devices/{id}/ops/{op} */
enum MHD_Result web_ops_route(const web_request_t *req, gripper_t *g, const char *op);
/* web_ops.c: the last long operation the web started on g, for the state
 * (null when none). */
void web_ops_last_write(const web_ops_t *ops, struct json_writer *j, const char *key,
                        const gripper_t *g);
/* A JSON reply whose text came from json_writer_take(): takes ownership of it
 * (NULL: no reply, the connection is closed). */
enum MHD_Result web_reply_json_text(const web_request_t *req, unsigned http_status, char *text);
/* Detaches the web's owners from their devices (shutdown). */
void web_ops_forget(web_ops_t *ops);
/* web_sim.c: POST /api/devices/{id}/sim/{what} */
enum MHD_Result web_sim_route(const web_request_t *req, gripper_t *g, const char *what);
/* web_events.c: GET /api/devices/{id}/events */
/* GET /api/devices/{id}/scene: the physics scene's bodies and contacts
 * (web_scene.c). */
enum MHD_Result web_scene_route(const web_request_t *req, gripper_t *g, const char *rest);
enum MHD_Result web_events_route(const web_request_t *req, gripper_t *g);
/* web_script.c: GET /api/devices/{id}/script and .../script/console, POST
 * .../script/run and .../script/stop, PUT .../script/startup (rest: "") */
enum MHD_Result web_script_get(const web_request_t *req, gripper_t *g, const char *rest);
enum MHD_Result web_script_console(const web_request_t *req, gripper_t *g, const char *rest);
enum MHD_Result web_script_run(const web_request_t *req, gripper_t *g, const char *rest);
enum MHD_Result web_script_stop(const web_request_t *req, gripper_t *g, const char *rest);
enum MHD_Result web_script_startup(const web_request_t *req, gripper_t *g, const char *rest);
/* web_store.c: /api/devices/{id}/files[/NAME] (rest: what follows "files";
 * whether there is a store is asked first, then the path and method) */
enum MHD_Result web_files_route(const web_request_t *req, gripper_t *g, const char *rest);
/* The host path of a store file the web names ("NAME.lua" or
 * "/user/NAME.lua") into path: NULL, else why it is refused (no store, not a
 * store name, one of wsgsim's own files). */
const char *web_store_path(const gripper_t *g, const char *name, char *path, size_t cap);
/* The same, and the file exists and is a regular file. */
const char *web_store_check_file(const gripper_t *g, const char *name, char *path, size_t cap);
/* "PATH: reason" (script_read_file's why) -> "reason": a reply names the
 * store's file, never the host's path. */
const char *web_store_reason(const char *why, const char *path);
/* web_system.c: GET /api/devices/{id}/system[?since=N] */
enum MHD_Result web_system_route(const web_request_t *req, gripper_t *g);
/* web_static.c: GET /, /devices/{id}, /static/NAME; false: not a page path */
bool web_static_route(const web_request_t *req, enum MHD_Result *result);
/* web_static.c: the files of web_system_file_t, none read yet / freed. */
void web_static_init(web_system_file_t *files);
void web_static_release(web_system_file_t *files);

#endif
