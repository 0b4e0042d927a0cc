/* Sessions: one per TCP connection or UDP peer. Bytes in, whole lines out. */
#include <string.h>

#include "hal_device.h"
#include "wsg_internal.h"

void session_reset_settings(wsg_session_t *s)
{
    const hal_device_config_t *cfg = hal_device_config();
    s->verbose = false;
    s->pwt_mm = cfg->default_pwt_mm;
    s->clt_mm = cfg->default_clt_mm;
    s->bye_received = false;
    memset(s->autosend, 0, sizeof(s->autosend));
    gcl_linebuf_reset(&s->input);
}

wsg_session_t *wsg_session_open(wsg_device_t *dev, wsg_transport_t transport,
                                const wsg_session_io_t *io, void *io_ctx)
{
    for (unsigned i = 0; i < WSG_MAX_SESSIONS; i++) {
        wsg_session_t *s = &dev->sessions[i];
        if (s->in_use) {
            continue;
        }
        memset(s, 0, sizeof(*s));
        s->in_use = true;
        s->index = (uint8_t)i;
        s->generation = ++dev->next_generation;
        s->transport = transport;
        s->io = io;
        s->io_ctx = io_ctx;
        session_reset_settings(s);
        return s;
    }
    return NULL;
}

wsg_session_t *session_lookup(wsg_device_t *dev, uint8_t index, uint64_t generation)
{
    if (index >= WSG_MAX_SESSIONS) {
        return NULL;
    }
    wsg_session_t *s = &dev->sessions[index];
    return (s->in_use && s->generation == generation) ? s : NULL;
}

static void handle_completed_line(wsg_device_t *dev, wsg_session_t *s)
{
    const gcl_linebuf_t *lb = &s->input;
    s->lines_in++;
    if (dev->hooks != NULL && dev->hooks->line_in != NULL) {
        dev->hooks->line_in(dev->hooks_ctx, s, lb->text, lb->len);
    }
    dispatch_line(dev, s, lb->text, lb->len, gcl_linebuf_status(lb));
}

void wsg_session_input(wsg_device_t *dev, wsg_session_t *s, const uint8_t *bytes, size_t len)
{
    for (size_t i = 0; i < len && !s->bye_received; i++) {
        if (gcl_linebuf_feed(&s->input, bytes[i])) {
            handle_completed_line(dev, s);
        }
    }
}

void wsg_session_end_datagram(wsg_device_t *dev, wsg_session_t *s)
{
    if (!s->bye_received && gcl_linebuf_flush(&s->input)) {
        handle_completed_line(dev, s);
    }
}

bool wsg_session_wants_close(const wsg_session_t *s)
{
    return s->bye_received;
}

bool wsg_session_has_autosend(const wsg_session_t *s)
{
    for (unsigned i = 0; i < AS_COUNT; i++) {
        if (s->autosend[i].interval_ms != 0u) {
            return true;
        }
    }
    return false;
}

/* The manual ends a connection with BYE(); the device copes without it. */
static void note_missing_bye(wsg_device_t *dev, const wsg_session_t *s, wsg_close_reason_t reason)
{
    bool missing =
        reason == WSG_CLOSE_DROPPED && !s->bye_received && s->transport == WSG_TRANSPORT_STREAM;
    if (missing && dev->hooks != NULL && dev->hooks->tolerated != NULL) {
        dev->hooks->tolerated(dev->hooks_ctx, s, "BYE", "connection closed without BYE()");
    }
}

void wsg_session_close(wsg_device_t *dev, wsg_session_t *s, wsg_close_reason_t reason)
{
    if (!s->in_use) {
        return;
    }
    bool raise_fast_stop = reason == WSG_CLOSE_DROPPED && !s->bye_received &&
                           s->transport == WSG_TRANSPORT_STREAM &&
                           hal_device_config()->disconnect_raises_faststop;
    note_missing_bye(dev, s, reason);
    s->in_use = false;
    s->io = NULL;
    if (raise_fast_stop) {
        wsg_device_fast_stop(dev, "connection closed without BYE");
    }
}

void session_send(wsg_device_t *dev, wsg_session_t *s, textbuf_t *tb, wsg_line_kind_t kind)
{
    if (!s->in_use || s->io == NULL) {
        return;
    }
    textbuf_put_char(tb, '\n');
    if (tb->overflow) {
        /* never hand out a cut line: report the overrun instead */
        textbuf_init(tb, tb->data, tb->cap);
        textbuf_put_str(tb, "ERR REPLY 27\n");
    }
    s->lines_out++;
    if (dev->hooks != NULL && dev->hooks->line_out != NULL) {
        dev->hooks->line_out(dev->hooks_ctx, s, tb->data, tb->len);
    }
    s->io->write_line(s->io_ctx, tb->data, tb->len, kind);
}

void session_send_text(wsg_device_t *dev, wsg_session_t *s, const char *text)
{
    char storage[WSG_REPLY_MAX];
    textbuf_t tb;
    textbuf_init(&tb, storage, sizeof(storage));
    textbuf_put_str(&tb, text);
    session_send(dev, s, &tb, WSG_LINE_REPLY);
}

/* "ACK HOME", "FIN MOVE" */
void session_send_word(wsg_device_t *dev, wsg_session_t *s, const char *word, const char *name)
{
    char storage[WSG_REPLY_MAX];
    textbuf_t tb;
    textbuf_init(&tb, storage, sizeof(storage));
    textbuf_put_str(&tb, word);
    textbuf_put_char(&tb, ' ');
    textbuf_put_str(&tb, name);
    session_send(dev, s, &tb, WSG_LINE_REPLY);
}

void session_send_error(wsg_device_t *dev, wsg_session_t *s, const char *name, wsg_status_t status)
{
    char storage[WSG_REPLY_MAX];
    textbuf_t tb;
    textbuf_init(&tb, storage, sizeof(storage));
    textbuf_put_str(&tb, "ERR ");
    textbuf_put_str(&tb, name[0] != '\0' ? name : "?");
    textbuf_put_char(&tb, ' ');
    textbuf_put_uint(&tb, (uint32_t)status);
    if (s->verbose) {
        textbuf_put_char(&tb, ' ');
        textbuf_put_str(&tb, wsg_status_description(status));
    }
    session_send(dev, s, &tb, WSG_LINE_REPLY);
    s->cmd_failed = true;
    flags_set(dev, SF_CMD_FAILURE, true);
}
