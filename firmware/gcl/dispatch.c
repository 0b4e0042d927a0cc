/* SPDX-License-Identifier: BSD-3-Clause */
/* Line → command → handler, and the one place that turns a failed
 * handler into an ERR line. */
#include "gcl/gcl_internal.h"
#include "priv/small_bytes.h"

#define CALL WSG_GCL_FORM_CALL
#define QUERY WSG_GCL_FORM_QUERY
#define INDEXED WSG_GCL_FORM_INDEXED
#define SET WSG_GCL_FORM_SET

_Static_assert(CALL == GCL_FORM_CALL && QUERY == GCL_FORM_QUERY &&
                   INDEXED == GCL_FORM_INDEXED_QUERY && SET == GCL_FORM_SET,
               "the public form bits are the parser's");
_Static_assert(WSG_GCL_NAME_MAX == GCL_NAME_MAX && WSG_GCL_ARGS_MAX == GCL_ARGS_MAX,
               "the public limits are the parser's");

static const cmd_entry_t commands[] = {
    {{"VERBOSE", SET | QUERY, 0, 0}, wsg_cmd_verbose},
    {{"BYE", CALL, 0, 0}, wsg_cmd_bye},
    {{"HOME", CALL, 0, 1}, wsg_cmd_home},
    {{"MOVE", CALL, 1, 2}, wsg_cmd_move},
    {{"GRIP", CALL, 0, 3}, wsg_cmd_grip},
    {{"RELEASE", CALL, 0, 2}, wsg_cmd_release},
    {{"PWT", QUERY | SET, 0, 0}, wsg_cmd_pwt},
    {{"CLT", QUERY | SET, 0, 0}, wsg_cmd_clt},
    {{"POS", QUERY, 0, 0}, wsg_cmd_pos},
    {{"SPEED", QUERY, 0, 0}, wsg_cmd_speed},
    {{"FORCE", QUERY, 0, 0}, wsg_cmd_force},
    {{"GRIPSTATE", QUERY, 0, 0}, wsg_cmd_gripstate},
    {{"DEVTYPE", QUERY, 0, 0}, wsg_cmd_devtype},
    {{"VERSION", QUERY, 0, 0}, wsg_cmd_version},
    {{"SN", QUERY, 0, 0}, wsg_cmd_sn},
    {{"TAG", QUERY, 0, 0}, wsg_cmd_tag},
    {{"SYSFLAGS", QUERY | INDEXED, 0, 0}, wsg_cmd_sysflags},
    {{"TEMP", QUERY, 0, 0}, wsg_cmd_temp},
    {{"AUTOSEND", CALL, 2, 3}, wsg_cmd_autosend},
    {{"STOP", CALL, 0, 0}, wsg_cmd_stop},
    {{"FASTSTOP", CALL, 0, 0}, wsg_cmd_faststop},
    {{"FSACK", CALL, 0, 0}, wsg_cmd_fsack},
    {{"TARE", CALL, 0, 1}, wsg_cmd_tare},
    {{"GRIPSTATS", QUERY | INDEXED, 0, 0}, wsg_cmd_gripstats},
    {{"FDATA", QUERY | INDEXED, 0, 0}, wsg_cmd_fdata},
    {{"FTYPE", QUERY | INDEXED, 0, 0}, wsg_cmd_ftype},
    {{"FFLAGS", QUERY | INDEXED, 0, 0}, wsg_cmd_fflags},
};

unsigned wsg_gcl_command_count(void)
{
    return (unsigned)(sizeof(commands) / sizeof(commands[0]));
}

const wsg_gcl_command_t *wsg_gcl_command_at(unsigned i)
{
    return i < wsg_gcl_command_count() ? &commands[i].info : NULL;
}

/* Names are a few letters: an open loop beats a library call on each. */
static bool same_name(const char *a, const char *b)
{
    while (*a != '\0' && *a == *b) {
        a++;
        b++;
    }
    return *a == *b;
}

static const cmd_entry_t *dispatch_find(const char *name)
{
    for (size_t i = 0; i < sizeof(commands) / sizeof(commands[0]); i++) {
        const char *known = commands[i].info.name;
        if (known[0] == name[0] && same_name(known, name)) {
            return &commands[i];
        }
    }
    return NULL;
}

/* dispatch_find(), trying the connection's previous command first. */
static const cmd_entry_t *find_for(gcl_conn_t *g, const char *name)
{
    const cmd_entry_t *last = g->last_command;
    if (last != NULL && same_name(last->info.name, name)) {
        return last;
    }
    const cmd_entry_t *entry = dispatch_find(name);
    if (entry != NULL) {
        g->last_command = entry;
    }
    return entry;
}

int wsg_gcl_command_index(const char *name)
{
    const cmd_entry_t *entry = dispatch_find(name);
    return entry != NULL ? (int)(entry - commands) : -1;
}

static wsg_status_t check_shape(const cmd_entry_t *entry, const gcl_command_t *cmd)
{
    if ((entry->info.forms & (unsigned)cmd->form) == 0u) {
        return E_CMD_FORMAT_ERROR;
    }
    if (cmd->form != GCL_FORM_CALL) {
        return E_SUCCESS;
    }
    if (cmd->argc < entry->info.min_args) {
        return E_NOT_ENOUGH_PARAMS;
    }
    if (cmd->argc > entry->info.max_args) {
        return E_NO_PARAM_EXPECTED;
    }
    return E_SUCCESS;
}

static void report_done(gcl_conn_t *g, const gcl_command_t *cmd, const cmd_entry_t *entry,
                        wsg_status_t status)
{
    int index = entry != NULL ? (int)(entry - commands) : -1;
    for (const wsg_gcl_observer_t *o = gcl_observers(g); o != NULL; o = o->next) {
        if (o->command_done != NULL) {
            o->command_done(o->ctx, conn_public(g->conn), cmd->name, index, (unsigned)cmd->form,
                            cmd->argc, status);
        }
    }
}

static bool is_blank(const char *line, size_t len)
{
    for (size_t i = 0; i < len; i++) {
        if (line[i] != ' ' && line[i] != '\t') {
            return false;
        }
    }
    return true;
}

static bool is_last_query(const gcl_conn_t *g, const char *line, size_t len)
{
    if (len != g->query_line_len) {
        return false;
    }
    for (size_t i = 0; i < len; i++) {
        if (line[i] != g->query_line[i]) {
            return false;
        }
    }
    return len != 0u;
}

/* Only a query its command answers is remembered: its repeats then run the
 * handler without a shape check (the slow path gives the others their ERR). */
static void remember_query(gcl_conn_t *g, const char *line, size_t len, const cmd_entry_t *entry)
{
    if (len > sizeof(g->query_line) || (entry->info.forms & (unsigned)GCL_FORM_QUERY) == 0u) {
        return;
    }
    wsg_small_copy(g->query_line, line, len);
    g->query_line_len = (uint8_t)len;
    const char *name = entry->info.name; /* at most GCL_NAME_MAX letters */
    bool ended = false;
    g->query_name_len = 0;
    for (size_t i = 0; i < sizeof(g->query_name); i++) {
        ended = ended || name[i] == '\0';
        g->query_name[i] = ended ? '\0' : name[i]; /* the rest NUL, as a parse leaves it */
        g->query_name_len += !ended;
    }
    g->query_entry = entry;
}

/* Queries only read; a line without a known command runs no handler. */
static bool ran_handler_that_acts(const cmd_entry_t *entry, const gcl_command_t *cmd)
{
    return entry != NULL && cmd->form != GCL_FORM_QUERY && cmd->form != GCL_FORM_INDEXED_QUERY;
}

static void sense_for_line(gcl_conn_t *g, wsg_device_t *dev)
{
    if (g->quiet_since_sense) {
        wsg_device_sense_if_moved_on(dev);
    } else {
        wsg_device_sense(dev); /* answer from the newest reading */
    }
}

/* A command that passed the line, name and syntax checks: an injected
 * failure answers instead of it if the simulation armed one, then its shape
 * is checked and its handler runs. */
static wsg_status_t run_command(gcl_conn_t *g, wsg_device_t *dev, const cmd_entry_t *entry,
                                const gcl_command_t *cmd)
{
    wsg_status_t status = E_SUCCESS;
    if (wsg_device_failure_armed(g->conn->dev) &&
        wsg_device_take_injected_failure(dev, cmd->name, &status)) {
        return status;
    }
    status = check_shape(entry, cmd);
    if (status != E_SUCCESS) {
        return status;
    }
    size_t name_len = 0;
    while (cmd->name[name_len] != '\0') {
        name_len++;
    }
    cmd_ctx_t ctx = {g, dev, cmd, name_len};
    return entry->handler(&ctx);
}

/* The end of every command line: its ERR line, SF_CMD_FAILURE (here and
 * only here, and in the final reply's event for long commands), the
 * observers, and whether the next line of this input may reuse the reading. */
static void finish_line(gcl_conn_t *g, wsg_device_t *dev, const gcl_command_t *cmd,
                        const cmd_entry_t *entry, wsg_status_t status)
{
    if (status != E_SUCCESS) {
        wsg_gcl_send_error(g, cmd->name, entry != NULL ? (int)(entry - commands) : -1, status);
    }
    g->cmd_failed = status != E_SUCCESS;
    wsg_device_note_result(dev, status);
    report_done(g, cmd, entry, status);
    g->quiet_since_sense = g->in_input && !ran_handler_that_acts(entry, cmd);
}

/* Which error a line earns is decided in this order: a bad line (too long,
 * control bytes), an unknown name, a syntax error, then the handler's own. */
void wsg_dispatch_line(gcl_conn_t *g, const char *line, size_t len, gcl_line_status_t line_status)
{
    if (line_status == GCL_LINE_OK && is_last_query(g, line, len)) {
        wsg_dispatch_repeated_query(g);
        return;
    }
    if (line_status == GCL_LINE_OK && is_blank(line, len)) {
        return; /* empty lines ("\r\n" keep-alives) are ignored */
    }
    wsg_device_t *dev = gcl_device(g);
    gcl_command_t cmd;
    wsg_status_t status = wsg_gcl_parse_line(line, len, &cmd);
    const cmd_entry_t *entry = cmd.name[0] != '\0' ? find_for(g, cmd.name) : NULL;
    if (line_status == GCL_LINE_OK && status == E_SUCCESS && entry != NULL &&
        cmd.form == GCL_FORM_QUERY) {
        remember_query(g, line, len, entry);
    }
    sense_for_line(g, dev);
    if (line_status != GCL_LINE_OK) {
        status = E_CMD_FORMAT_ERROR;
    } else if (cmd.name[0] != '\0' && entry == NULL) {
        status = E_CMD_UNKNOWN;
    } else if (status == E_SUCCESS) {
        status = run_command(g, dev, entry, &cmd);
    }
    finish_line(g, dev, &cmd, entry, status);
}

/* The connection's last plain query line again: the command its parse
 * gives is the command's name in the query form, without arguments or
 * index, so no parse runs. Only what a query's handler, the observers and
 * the injected failure read is set: arguments are read for argc > 0 only.
 * The common outcome (no failure armed, success) is written out; every
 * other goes the general way. */
void wsg_dispatch_repeated_query(gcl_conn_t *g)
{
    const cmd_entry_t *entry = g->query_entry;
    wsg_device_t *dev = gcl_device(g);
    gcl_command_t cmd;
    WSG_COPY_FIXED(cmd.name, g->query_name, sizeof(cmd.name));
    cmd.form = GCL_FORM_QUERY;
    cmd.index = 0;
    cmd.argc = 0;
    sense_for_line(g, dev);
    if (wsg_device_failure_armed(g->conn->dev)) {
        finish_line(g, dev, &cmd, entry, run_command(g, dev, entry, &cmd));
        return;
    }
    cmd_ctx_t ctx = {g, dev, &cmd, g->query_name_len};
    wsg_status_t status = entry->handler(&ctx); /* its shape was checked when remembered */
    if (status != E_SUCCESS) {
        finish_line(g, dev, &cmd, entry, status);
        return;
    }
    /* finish_line() of a success, step by step */
    g->cmd_failed = false;
    if (wsg_flags_get(g->conn->dev, SF_CMD_FAILURE)) { /* clearing a clear flag changes nothing */
        wsg_device_note_result(dev, E_SUCCESS);
    }
    if (gcl_observers(g) != NULL) {
        report_done(g, &cmd, entry, E_SUCCESS);
    }
    g->quiet_since_sense = g->in_input; /* a query does not act */
}
