/* SPDX-License-Identifier: BSD-3-Clause */
/* The custom command channel of a user script (wsg_script.h): the IDs the
 * script claimed, the queue of their requests, which connections are hosts
 * and the script's reply frames. No interpreter here: the port runs the
 * script and calls these. */
#include <string.h>

#include "bin/bin_internal.h"

_Static_assert(WSG_SCRIPT_QUEUE_DEPTH >= 1 && WSG_SCRIPT_QUEUE_DEPTH <= 255,
               "WSG_SCRIPT_QUEUE_DEPTH must fit the queue's 8-bit counters");
_Static_assert(WSG_SCRIPT_REQUEST_MAX >= WSG_BIN_PAYLOAD_MAX,
               "a queued request must hold every payload the framer keeps");

static dev_script_t *script_of(wsg_device_t *dev)
{
    return &dev_of(dev)->script;
}

bool wsg_script_registered(const wsg_device_t *dev, uint8_t id)
{
    const dev_script_t *s = &dev_of_const(dev)->script;
    return (s->registered[id / 32u] & (1u << (id % 32u))) != 0u;
}

wsg_status_t wsg_script_register(wsg_device_t *dev, int id)
{
    if (id < 0 || id > 255 || id == 0xAA || wsg_bin_command_name((uint8_t)id) != NULL) {
        return E_INVALID_PARAMETER;
    }
    script_of(dev)->registered[id / 32] |= 1u << (id % 32);
    return E_SUCCESS;
}

void wsg_script_unregister(wsg_device_t *dev, int id)
{
    if (id >= 0 && id <= 255) {
        script_of(dev)->registered[id / 32] &= ~(1u << (id % 32));
    }
}

void wsg_script_release_all(wsg_device_t *dev)
{
    dev_script_t *s = script_of(dev);
    memset(s->registered, 0, sizeof(s->registered));
    s->head = 0;
    s->count = 0;
}

size_t wsg_script_pending(const wsg_device_t *dev)
{
    return dev_of_const(dev)->script.count;
}

bool wsg_script_take(wsg_device_t *dev, wsg_script_request_t *out)
{
    dev_script_t *s = script_of(dev);
    if (s->count == 0) {
        return false;
    }
    *out = s->queue[s->head];
    s->head = (uint8_t)((s->head + 1u) % WSG_SCRIPT_QUEUE_DEPTH);
    s->count--;
    return true;
}

/* Called by the driver for a request whose ID the script claimed: queued
 * (no reply now; the script answers), or E_OVERRUN when the queue is full. */
wsg_status_t wsg_bin_script_queue(bin_conn_t *b, const wsg_bin_frame_t *frame)
{
    dev_script_t *s = &b->conn->dev->script;
    if (s->count >= WSG_SCRIPT_QUEUE_DEPTH) {
        return E_OVERRUN;
    }
    wsg_script_request_t *r = &s->queue[(s->head + s->count) % WSG_SCRIPT_QUEUE_DEPTH];
    r->conn_id = b->conn->id;
    r->id = frame->id;
    r->length = frame->length;
    memcpy(r->payload, frame->payload, frame->length);
    s->count++;
    return BIN_QUEUED;
}

void wsg_bin_script_note_host(bin_conn_t *b)
{
    b->conn->dev->script.last_host_id = b->conn->id;
}

/* A closed connection's requests are dropped unanswered; the others keep
 * their order. */
void wsg_bin_script_drop_conn(bin_conn_t *b)
{
    dev_script_t *s = &b->conn->dev->script;
    uint8_t kept = 0;
    for (uint8_t k = 0; k < s->count; k++) {
        const wsg_script_request_t *r = &s->queue[(s->head + k) % WSG_SCRIPT_QUEUE_DEPTH];
        if (r->conn_id != b->conn->id) {
            s->queue[(s->head + kept) % WSG_SCRIPT_QUEUE_DEPTH] = *r;
            kept++;
        }
    }
    s->count = kept;
}

static bool is_host(const conn_t *c)
{
    return c->open && c->drv == &wsg_bin_driver &&
           !((const bin_conn_t *)(const void *)c->proto)->announced;
}

static const conn_t *host_by_id(const wsg_dev_t *dev, uint64_t id)
{
    for (const conn_t *c = dev->conns; c != NULL && id != 0; c = c->next) {
        if (c->id == id) {
            return is_host(c) ? c : NULL;
        }
    }
    return NULL;
}

bool wsg_script_online(const wsg_device_t *dev)
{
    return wsg_script_reply_host(dev, 0) != 0;
}

uint64_t wsg_script_reply_host(const wsg_device_t *dev, uint64_t preferred)
{
    const wsg_dev_t *d = dev_of_const(dev);
    if (host_by_id(d, preferred) != NULL) {
        return preferred;
    }
    if (host_by_id(d, d->script.last_host_id) != NULL) {
        return d->script.last_host_id;
    }
    uint64_t newest = 0;
    for (const conn_t *c = d->conns; c != NULL; c = c->next) {
        newest = is_host(c) ? c->id : newest;
    }
    return newest;
}

wsg_status_t wsg_script_send(wsg_device_t *dev, uint64_t conn_id, uint8_t id,
                             const uint8_t *payload, size_t len, uint8_t *scratch, size_t cap)
{
    conn_t *c = (conn_t *)(uintptr_t)host_by_id(dev_of(dev), conn_id);
    if (c == NULL) {
        return E_NOT_AVAILABLE;
    }
    if (len > 0xFFFFu) {
        return E_RANGE_ERROR;
    }
    size_t n = wsg_bin_encode_frame(scratch, cap, id, payload, (uint16_t)len);
    if (n == 0) {
        return E_RANGE_ERROR;
    }
    wsg_conn_write(c, (const char *)scratch, n, WSG_MSG_REPLY);
    return E_SUCCESS;
}
