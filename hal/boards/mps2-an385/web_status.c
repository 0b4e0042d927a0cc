/* SPDX-License-Identifier: BSD-3-Clause */
#include "web_status.h"

#include <stdbool.h>
#include <string.h>

#include "app.h"
#include "lwip/apps/fs.h"
#include "lwip/apps/httpd.h"
#include "wsg/wsg_textbuf.h" /* the device's number formatting: no printf on the board */
#include "wsg/wsg_names.h"
#include "wsg/wsg_device.h"

#define STATE_PATH "/api/devices/0/state"

/* Responses from flash. HTTP/1.0 and "Connection: close": httpd closes after
 * each response, so their bodies end with the connection. */
#define HEADERS(status, type)                                                                      \
    "HTTP/1.0 " status "\r\nServer: wsgsim\r\nContent-Type: " type "\r\n"                          \
    "Cache-Control: no-store\r\nConnection: close\r\n\r\n"

#define PAGE_HEADERS HEADERS("200 OK", "text/html; charset=utf-8")

/* Polls the state every 500 ms, one request at a time. */
static const char page[] = PAGE_HEADERS
    "<!DOCTYPE html>\n"
    "<html><head><meta charset=\"utf-8\"><title>WSG status</title>\n"
    "<style>body{font:16px sans-serif;margin:2em}td{padding:2px 1em}</style></head>\n"
    "<body><h1>WSG gripper</h1>\n"
    "<table><tbody id=\"state\"></tbody></table>\n"
    "<p>The state as JSON: <a href=\"" STATE_PATH "\">" STATE_PATH "</a></p>\n"
    "<script>\n"
    "const rows = [['Width', 'position_mm', ' mm'], ['Speed', 'speed_mm_s', ' mm/s'],\n"
    "  ['Force', 'force_n', ' N'], ['Temperature', 'temperature_c', ' \\u00b0C']];\n"
    "function show(s) {\n"
    "  const table = document.getElementById('state');\n"
    "  table.textContent = '';\n"
    "  const add = (name, value) => {\n"
    "    const row = table.insertRow();\n"
    "    row.insertCell().textContent = name;\n"
    "    row.insertCell().textContent = value;\n"
    "  };\n"
    "  for (const [name, field, unit] of rows) add(name, s[field] + unit);\n"
    "  add('Grip state', s.grip_state.name + ' (' + s.grip_state.code + ')');\n"
    "  add('System flags', s.sysflags.set.join(' ') || 'none');\n"
    "}\n"
    "async function poll() {\n"
    "  try {\n"
    "    const reply = await fetch('" STATE_PATH "', {cache: 'no-store'});\n"
    "    show(await reply.json());\n"
    "  } catch (e) { /* the board restarted or the link is down: try again */ }\n"
    "  setTimeout(poll, 500);\n"
    "}\n"
    "poll();\n"
    "</script></body></html>\n";

static const char not_found[] = HEADERS("404 Not Found", "text/plain") "404 Not Found\n";
static const char bad_request[] = HEADERS("400 Bad Request", "text/plain") "400 Bad Request\n";
static const char not_implemented[] =
    HEADERS("501 Not Implemented", "text/plain") "501 Not Implemented: GET only\n";
static const char server_error[] =
    HEADERS("500 Internal Server Error", "text/plain") "500 Internal Server Error\n";

/* httpd asks for "/index.html" when "/" is requested, and for the error
 * pages by these names (LWIP_HTTPD_SUPPORT_EXTSTATUS). */
typedef struct {
    const char *path;
    const char *response;
    int len;
} flash_file_t;

static const flash_file_t flash_files[] = {
    {"/index.html", page, sizeof page - 1},
    {"/404.html", not_found, sizeof not_found - 1},
    {"/400.html", bad_request, sizeof bad_request - 1},
    {"/501.html", not_implemented, sizeof not_implemented - 1},
};

/* The state's response, built when httpd opens it and kept until httpd
 * closes it (httpd copies it into its segments, lwipopts.h). One slot per
 * httpd connection, so an open never finds them all in use. The body is at
 * most 556 bytes (every named flag set, every number at textbuf's limit). */
#define STATE_HEADER_MAX 160u
#define STATE_BODY_MAX 768u

typedef struct {
    bool in_use;
    char text[STATE_HEADER_MAX + STATE_BODY_MAX];
} state_slot_t;

static state_slot_t slots[MEMP_NUM_PARALLEL_HTTPD_CONNS];

/* lwIP's fs.c calls these (LWIP_HTTPD_CUSTOM_FILES); it has no header for them. */
int fs_open_custom(struct fs_file *file, const char *name);
void fs_close_custom(struct fs_file *file);

static void put_key(wsg_textbuf_t *tb, const char *key)
{
    wsg_textbuf_put_quoted(tb, key);
    wsg_textbuf_put_char(tb, ':');
}

static void put_float_field(wsg_textbuf_t *tb, const char *key, float value)
{
    put_key(tb, key);
    wsg_textbuf_put_float(tb, value);
    wsg_textbuf_put_char(tb, ',');
}

static void put_grip_state(wsg_textbuf_t *tb, wsg_grip_state_t state)
{
    put_key(tb, "grip_state");
    wsg_textbuf_put_str(tb, "{\"code\":");
    wsg_textbuf_put_uint(tb, (uint32_t)state);
    wsg_textbuf_put_str(tb, ",\"name\":");
    wsg_textbuf_put_quoted(tb, wsg_grip_state_name(state));
    wsg_textbuf_put_char(tb, '}');
}

static void put_sysflags(wsg_textbuf_t *tb, uint32_t flags)
{
    put_key(tb, "sysflags");
    wsg_textbuf_put_str(tb, "{\"value\":");
    wsg_textbuf_put_uint(tb, flags);
    wsg_textbuf_put_str(tb, ",\"set\":[");
    bool first = true;
    for (unsigned bit = 0; bit < WSG_SYSFLAG_COUNT; bit++) {
        const char *name = wsg_sysflag_name(bit);
        if ((flags & WSG_FLAG(bit)) == 0u || name == NULL) {
            continue; /* a reserved bit has no name and is never set */
        }
        if (!first) {
            wsg_textbuf_put_char(tb, ',');
        }
        wsg_textbuf_put_quoted(tb, name);
        first = false;
    }
    wsg_textbuf_put_str(tb, "]}");
}

/* The host API's names and units (docs/web.md), one line. */
static void put_state(wsg_textbuf_t *tb, const wsg_snapshot_t *snap)
{
    wsg_textbuf_put_char(tb, '{');
    put_float_field(tb, "position_mm", snap->position_mm);
    put_float_field(tb, "speed_mm_s", snap->speed_mm_s);
    put_float_field(tb, "force_n", snap->force_n);
    put_float_field(tb, "temperature_c", snap->temperature_c);
    put_grip_state(tb, snap->grip_state);
    wsg_textbuf_put_char(tb, ',');
    put_sysflags(tb, snap->flags);
    wsg_textbuf_put_str(tb, "}\n");
}

static void open_flash(struct fs_file *file, const char *response, int len)
{
    file->data = response;
    file->len = len;
    file->index = len; /* all of it is in memory: nothing for fs_read */
    file->pextension = NULL;
    file->flags = FS_FILE_FLAGS_HEADER_INCLUDED;
}

/* The body is written after room for the headers; the headers, whose
 * Content-Length needs the body's, are then placed right before it. */
static void open_state(struct fs_file *file, state_slot_t *slot)
{
    char *body = slot->text + STATE_HEADER_MAX;
    wsg_textbuf_t tb;
    wsg_textbuf_init(&tb, body, STATE_BODY_MAX);
    put_state(&tb, wsg_device_snapshot(app_device()));
    if (tb.overflow) {
        open_flash(file, server_error, sizeof server_error - 1);
        return;
    }
    char headers[STATE_HEADER_MAX];
    wsg_textbuf_t hb;
    wsg_textbuf_init(&hb, headers, sizeof headers);
    wsg_textbuf_put_str(&hb, "HTTP/1.0 200 OK\r\nServer: wsgsim\r\n"
                             "Content-Type: application/json\r\nContent-Length: ");
    wsg_textbuf_put_uint(&hb, (uint32_t)tb.len);
    wsg_textbuf_put_str(&hb, "\r\nCache-Control: no-store\r\nConnection: close\r\n\r\n");
    char *start = body - hb.len;
    memcpy(start, headers, hb.len);
    open_flash(file, start, (int)(hb.len + tb.len));
    file->pextension = slot;
    slot->in_use = true;
}

static state_slot_t *free_slot(void)
{
    for (unsigned i = 0; i < MEMP_NUM_PARALLEL_HTTPD_CONNS; i++) {
        if (!slots[i].in_use) {
            return &slots[i];
        }
    }
    return NULL;
}

int fs_open_custom(struct fs_file *file, const char *name)
{
    for (unsigned i = 0; i < sizeof flash_files / sizeof flash_files[0]; i++) {
        if (strcmp(name, flash_files[i].path) == 0) {
            open_flash(file, flash_files[i].response, flash_files[i].len);
            return 1;
        }
    }
    if (strcmp(name, STATE_PATH) != 0) {
        return 0;
    }
    state_slot_t *slot = free_slot();
    if (slot == NULL) { /* not while each connection has its slot */
        open_flash(file, server_error, sizeof server_error - 1);
        return 1;
    }
    open_state(file, slot);
    return 1;
}

void fs_close_custom(struct fs_file *file)
{
    state_slot_t *slot = file->pextension;
    if (slot != NULL) {
        slot->in_use = false;
    }
}

void web_status_init(void)
{
    httpd_init();
}
