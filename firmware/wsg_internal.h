/* Declarations shared by the core's modules; not part of the port API. */
#ifndef WSG_INTERNAL_H
#define WSG_INTERNAL_H

#include "gcl_parse.h"
#include "textbuf.h"
#include "wsg_device.h"

/* session.c */
void session_send(wsg_device_t *dev, wsg_session_t *s, textbuf_t *tb, wsg_line_kind_t kind);
void session_send_text(wsg_device_t *dev, wsg_session_t *s, const char *text);
void session_send_word(wsg_device_t *dev, wsg_session_t *s, const char *word, const char *name);
void session_send_error(wsg_device_t *dev, wsg_session_t *s, const char *name, wsg_status_t status);
wsg_session_t *session_lookup(wsg_device_t *dev, uint8_t index, uint64_t generation);
void session_reset_settings(wsg_session_t *s);

/* dispatch.c */
void dispatch_line(wsg_device_t *dev, wsg_session_t *s, const char *line, size_t len,
                   gcl_line_status_t line_status);

/* flags.c */
void flags_refresh(wsg_device_t *dev);
void flags_set(wsg_device_t *dev, wsg_sysflag_t flag, bool on);
bool flags_get(const wsg_device_t *dev, wsg_sysflag_t flag);
/* A cause that raises FAST STOP by itself and blocks its acknowledge. */
bool flags_severe_fault(const wsg_device_t *dev);
/* The register as session s reads it: SF_CMD_FAILURE is that session's own. */
uint32_t flags_for_session(const wsg_device_t *dev, const wsg_session_t *s);

/* motion.c */
wsg_status_t motion_check_allowed(wsg_device_t *dev, bool needs_reference);
/* A MOVE arriving while a MOVE runs: ends the running one (ERR MOVE 19 to its
 * issuer) so that the new one takes the axis over from where it is. False
 * when nothing was superseded (strict rejection configured, or no MOVE). */
bool motion_supersede_move(wsg_device_t *dev);
void motion_begin(wsg_device_t *dev, wsg_session_t *owner, wsg_motion_kind_t kind);
void motion_abort(wsg_device_t *dev, wsg_status_t status);
void motion_step(wsg_device_t *dev);
const char *motion_command_name(wsg_motion_kind_t kind);
void grip_set_state(wsg_device_t *dev, wsg_grip_state_t state);
void grip_monitor_step(wsg_device_t *dev);
void motion_block_watch_step(wsg_device_t *dev);

/* autosend.c */
bool autosend_value_by_name(const char *name, wsg_autosend_value_t *value);
bool autosend_value_is_numeric(wsg_autosend_value_t value);
void autosend_put_value(const wsg_device_t *dev, const wsg_session_t *s, wsg_autosend_value_t value,
                        textbuf_t *tb);
void autosend_step(wsg_device_t *dev);
uint64_t autosend_next_due_us(const wsg_device_t *dev);

#endif
