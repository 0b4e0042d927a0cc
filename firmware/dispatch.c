/* Line → command → handler, and the one place that turns a failed
 * handler into an ERR line. */
#include <string.h>

#include "dispatch.h"
#include "hal_log.h"

#define CALL GCL_FORM_CALL
#define QUERY GCL_FORM_QUERY
#define INDEXED GCL_FORM_INDEXED_QUERY
#define SET GCL_FORM_SET

static const cmd_entry_t commands[] = {
    {"VERBOSE", SET | QUERY, 0, 0, cmd_verbose},
    {"BYE", CALL, 0, 0, cmd_bye},
    {"HOME", CALL, 0, 1, cmd_home},
    {"MOVE", CALL, 1, 2, cmd_move},
    {"GRIP", CALL, 0, 3, cmd_grip},
    {"RELEASE", CALL, 0, 2, cmd_release},
    {"PWT", QUERY | SET, 0, 0, cmd_pwt},
    {"CLT", QUERY | SET, 0, 0, cmd_clt},
    {"POS", QUERY, 0, 0, cmd_pos},
    {"SPEED", QUERY, 0, 0, cmd_speed},
    {"FORCE", QUERY, 0, 0, cmd_force},
    {"GRIPSTATE", QUERY, 0, 0, cmd_gripstate},
    {"DEVTYPE", QUERY, 0, 0, cmd_devtype},
    {"VERSION", QUERY, 0, 0, cmd_version},
    {"SN", QUERY, 0, 0, cmd_sn},
    {"TAG", QUERY, 0, 0, cmd_tag},
    {"SYSFLAGS", QUERY | INDEXED, 0, 0, cmd_sysflags},
    {"TEMP", QUERY, 0, 0, cmd_temp},
    {"AUTOSEND", CALL, 2, 3, cmd_autosend},
    {"STOP", CALL, 0, 0, cmd_stop},
    {"FASTSTOP", CALL, 0, 0, cmd_faststop},
    {"FSACK", CALL, 0, 0, cmd_fsack},
    {"TARE", CALL, 0, 1, cmd_tare},
    {"GRIPSTATS", QUERY | INDEXED, 0, 0, cmd_gripstats},
    {"FDATA", QUERY | INDEXED, 0, 0, cmd_fdata},
    {"FTYPE", QUERY | INDEXED, 0, 0, cmd_ftype},
    {"FFLAGS", QUERY | INDEXED, 0, 0, cmd_fflags},
};

unsigned dispatch_count(void)
{
    return (unsigned)(sizeof(commands) / sizeof(commands[0]));
}

const cmd_entry_t *dispatch_at(unsigned i)
{
    return i < dispatch_count() ? &commands[i] : NULL;
}

const cmd_entry_t *dispatch_find(const char *name)
{
    for (size_t i = 0; i < sizeof(commands) / sizeof(commands[0]); i++) {
        if (strcmp(commands[i].name, name) == 0) {
            return &commands[i];
        }
    }
    return NULL;
}

static wsg_status_t check_shape(const cmd_entry_t *entry, const gcl_command_t *cmd)
{
    if ((entry->forms & (unsigned)cmd->form) == 0u) {
        return E_CMD_FORMAT_ERROR;
    }
    if (cmd->form != GCL_FORM_CALL) {
        return E_SUCCESS;
    }
    if (cmd->argc < entry->min_args) {
        return E_NOT_ENOUGH_PARAMS;
    }
    if (cmd->argc > entry->max_args) {
        return E_NO_PARAM_EXPECTED;
    }
    return E_SUCCESS;
}

static void report_done(wsg_device_t *dev, const wsg_session_t *s, const gcl_command_t *cmd,
                        wsg_status_t status)
{
    if (dev->hooks != NULL && dev->hooks->command_done != NULL) {
        dev->hooks->command_done(dev->hooks_ctx, s, cmd->name, (unsigned)cmd->form, cmd->argc,
                                 status);
    }
}

static wsg_status_t run_command(wsg_device_t *dev, wsg_session_t *s, const cmd_entry_t *entry,
                                const gcl_command_t *cmd)
{
    wsg_status_t status = check_shape(entry, cmd);
    if (status != E_SUCCESS) {
        return status;
    }
    cmd_ctx_t ctx = {dev, s, cmd};
    return entry->handler(&ctx);
}

void wsg_device_inject_failure(wsg_device_t *dev, const char *name, wsg_status_t status)
{
    wsg_injected_failure_t *f = &dev->injected_failure;
    strncpy(f->name, name, sizeof(f->name) - 1);
    f->name[sizeof(f->name) - 1] = '\0';
    f->status = status;
    f->armed = true;
}

/* An armed injected failure for this command: consumes it. */
static bool take_injected_failure(wsg_device_t *dev, const gcl_command_t *cmd, wsg_status_t *status)
{
    wsg_injected_failure_t *f = &dev->injected_failure;
    if (!f->armed || strcmp(f->name, cmd->name) != 0) {
        return false;
    }
    f->armed = false;
    *status = f->status;
    hal_log(HAL_LOG_WARN, "injected failure answered");
    return true;
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

/* Which error a line earns is decided in this order: a bad line (too long,
 * control bytes), an unknown name, a syntax error, then the handler's own. */
void dispatch_line(wsg_device_t *dev, wsg_session_t *s, const char *line, size_t len,
                   gcl_line_status_t line_status)
{
    if (line_status == GCL_LINE_OK && is_blank(line, len)) {
        return; /* empty lines ("\r\n" keep-alives) are ignored */
    }
    gcl_command_t cmd;
    wsg_status_t status = gcl_parse_line(line, len, &cmd);
    flags_refresh(dev); /* answer from the newest hardware reading */
    const cmd_entry_t *entry = cmd.name[0] != '\0' ? dispatch_find(cmd.name) : NULL;
    if (line_status != GCL_LINE_OK) {
        status = E_CMD_FORMAT_ERROR;
    } else if (cmd.name[0] != '\0' && entry == NULL) {
        status = E_CMD_UNKNOWN;
    } else if (status == E_SUCCESS && !take_injected_failure(dev, &cmd, &status)) {
        status = run_command(dev, s, entry, &cmd);
    }
    if (status != E_SUCCESS) {
        session_send_error(dev, s, cmd.name, status);
    } else {
        s->cmd_failed = false;
        flags_set(dev, SF_CMD_FAILURE, false);
    }
    report_done(dev, s, &cmd, status);
}
