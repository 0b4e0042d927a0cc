/* SPDX-License-Identifier: BSD-3-Clause */
/* Finger interface (manual 3.3.1, 3.4). */
#include "gcl/gcl_internal.h"

static wsg_status_t finger_index(const cmd_ctx_t *ctx, int *index)
{
    if (ctx->cmd->form != GCL_FORM_INDEXED_QUERY) {
        *index = -1;
        return E_SUCCESS;
    }
    if (ctx->cmd->index < 0 || ctx->cmd->index >= WSG_FINGER_COUNT) {
        return E_INDEX_OUT_OF_BOUNDS;
    }
    *index = (int)ctx->cmd->index;
    return E_SUCCESS;
}

typedef void (*finger_writer_t)(wsg_textbuf_t *tb, const wsg_finger_t *finger);

/* NAME=[a,b] for both slots or NAME[i]=a for one. */
static wsg_status_t reply_fingers(cmd_ctx_t *ctx, finger_writer_t write)
{
    int index = 0;
    wsg_status_t status = finger_index(ctx, &index);
    if (status != E_SUCCESS) {
        return status;
    }
    char storage[WSG_REPLY_MAX];
    wsg_textbuf_t tb;
    wsg_textbuf_init(&tb, storage, sizeof(storage));
    wsg_textbuf_put_str(&tb, ctx->cmd->name);
    const wsg_finger_t *slots = wsg_device_snapshot(ctx->dev)->fingers->slot;
    if (index >= 0) {
        wsg_textbuf_put_char(&tb, '[');
        wsg_textbuf_put_int(&tb, index);
        wsg_textbuf_put_str(&tb, "]=");
        write(&tb, &slots[index]);
    } else {
        wsg_textbuf_put_str(&tb, "=[");
        for (int i = 0; i < WSG_FINGER_COUNT; i++) {
            if (i > 0) {
                wsg_textbuf_put_char(&tb, ',');
            }
            write(&tb, &slots[i]);
        }
        wsg_textbuf_put_char(&tb, ']');
    }
    wsg_reply_text(ctx, &tb);
    return E_SUCCESS;
}

/* One slot's FDATA value: a float (FMF), a vector of integer cell values
 * (DSA) or [] when the finger delivers no data. */
static void write_data(wsg_textbuf_t *tb, const wsg_finger_t *finger)
{
    if (finger->type == FINGER_FMF && finger->data_count == 1) {
        wsg_textbuf_put_float(tb, finger->data[0]);
        return;
    }
    wsg_textbuf_put_char(tb, '[');
    for (unsigned i = 0; i < finger->data_count; i++) {
        if (i > 0) {
            wsg_textbuf_put_char(tb, ',');
        }
        if (finger->type == FINGER_DSA) {
            wsg_textbuf_put_uint(tb, (uint32_t)finger->data[i]); /* raw 12-bit cells */
        } else {
            wsg_textbuf_put_float(tb, finger->data[i]);
        }
    }
    wsg_textbuf_put_char(tb, ']');
}

static void write_type(wsg_textbuf_t *tb, const wsg_finger_t *finger)
{
    wsg_textbuf_put_quoted(tb, wsg_finger_type_name(finger->type));
}

static void write_flags(wsg_textbuf_t *tb, const wsg_finger_t *finger)
{
    wsg_textbuf_put_bits(tb, finger->flags, WSG_FINGER_FLAG_COUNT);
}

wsg_status_t wsg_cmd_ftype(cmd_ctx_t *ctx)
{
    return reply_fingers(ctx, write_type);
}

wsg_status_t wsg_cmd_fflags(cmd_ctx_t *ctx)
{
    return reply_fingers(ctx, write_flags);
}

wsg_status_t wsg_cmd_fdata(cmd_ctx_t *ctx)
{
    int index = 0;
    wsg_status_t status = finger_index(ctx, &index);
    if (status != E_SUCCESS) {
        return status;
    }
    const wsg_fingers_t *fingers = wsg_device_snapshot(ctx->dev)->fingers;
    bool any = wsg_finger_has_data(&fingers->slot[0]) || wsg_finger_has_data(&fingers->slot[1]);
    if ((index >= 0 && !wsg_finger_has_data(&fingers->slot[index])) || !any) {
        return E_NOT_AVAILABLE;
    }
    return reply_fingers(ctx, write_data);
}

wsg_status_t wsg_cmd_tare(cmd_ctx_t *ctx)
{
    int32_t index = -1;
    if (ctx->cmd->argc == 1) {
        wsg_status_t status = wsg_arg_int(ctx, 0, &index);
        if (status != E_SUCCESS) {
            return status;
        }
        if (index < 0 || index >= WSG_FINGER_COUNT) {
            return E_INDEX_OUT_OF_BOUNDS;
        }
    }
    wsg_status_t status = wsg_op_tare(ctx->dev, (int)index);
    if (status != E_SUCCESS) {
        return status;
    }
    wsg_reply_ack(ctx);
    return E_SUCCESS;
}
