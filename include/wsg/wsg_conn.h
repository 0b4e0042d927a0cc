/* SPDX-License-Identifier: BSD-3-Clause */
/* Protocol-neutral connections and the protocol driver interface.
 *
 * A connection is bytes in, whole messages out, close. The port owns its
 * storage (a pool per server, a static array on a board) and moves bytes;
 * a protocol driver (GCL now, the binary protocol next) owns everything
 * protocol-specific: its per-connection state lives inside the connection,
 * it parses, calls the device's operations and formats every message.
 * The shape follows TinyUSB's usbd_class_driver_t. */
#ifndef WSG_CONN_H
#define WSG_CONN_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "wsg_device.h"

typedef enum {
    WSG_TRANSPORT_STREAM,   /* a connection (TCP): it can be lost, and closed on purpose */
    WSG_TRANSPORT_DATAGRAM, /* a peer (UDP): each datagram ends a message */
    /* A serial line (UART): a stream that is always there. Nothing is
     * connected or lost, so there is no disconnect to announce (the binary
     * 0x07 answers E_NOT_AVAILABLE) and none raises FAST STOP. */
    WSG_TRANSPORT_SERIAL,
} wsg_transport_t;

typedef enum {
    WSG_MSG_REPLY,  /* answers and final replies: a port never drops one */
    WSG_MSG_UPDATE, /* unsolicited values (AUTOSEND): may be dropped under back-pressure */
} wsg_msg_kind_t;

typedef enum {
    WSG_CLOSE_ANNOUNCED, /* the protocol said goodbye (BYE) */
    WSG_CLOSE_DROPPED,   /* the connection went away without it */
    WSG_CLOSE_EXPIRED,   /* a datagram peer that the port forgot, or a server-side timeout */
} wsg_close_reason_t;

/* How a connection hands out its messages: one call per whole message (a
 * GCL line with its '\n', a binary frame), which the port sends with one
 * send(): real clients compare one recv() with one reply. */
typedef struct {
    void (*write)(void *ctx, const char *bytes, size_t len, wsg_msg_kind_t kind);
    /* Optional: true while something interposed on the port's output holds
     * replies back (the control channel's DELAY); they still count as
     * queued, so a half-closed connection waits for them. */
    bool (*held)(void *ctx);
    /* Optional, needed under a timing profile (wsg_timing.h): the
     * processor has served the request the connection held. The port feeds
     * it the bytes it kept back (wsg_conn_input() took fewer than it was
     * given) and looks at wsg_conn_wants_close(): the request may have
     * been BYE. Called from inside the device's step. */
    void (*resume)(void *ctx);
} wsg_conn_io_t;

typedef struct wsg_conn {
    WSG_ALIGNED unsigned char storage[WSG_CONN_STORAGE_BYTES];
} wsg_conn_t;

typedef struct wsg_proto_driver {
    const char *name;
    /* Auto-detection: does a connection whose first byte is this one speak
     * this protocol? NULL: any byte (a catch-all, last in a table). */
    bool (*detect)(uint8_t first_byte);
    void (*open)(wsg_conn_t *c);
    /* returns the bytes taken: all of them, but under a timing profile it
     * stops after a whole request, which it holds until serve() */
    size_t (*input)(wsg_conn_t *c, const uint8_t *bytes, size_t len);
    void (*end_datagram)(wsg_conn_t *c);
    /* a long operation this connection started has ended (its owner's event) */
    void (*done)(wsg_conn_t *c, wsg_op_t op, wsg_status_t status);
    /* true while the driver keeps the connection busy (subscriptions) */
    bool (*busy)(const wsg_conn_t *c);
    void (*close)(wsg_conn_t *c, wsg_close_reason_t why);
    /* true while the driver holds part of a message: a line without its
     * end, a frame cut short (NULL: never) */
    bool (*partial)(const wsg_conn_t *c);
    /* runs the request input() held for the command processor (NULL: the
     * driver never holds one) */
    void (*serve)(wsg_conn_t *c);
} wsg_proto_driver_t;

/* The protocol drivers a connection opened without one may choose from, in
 * the order they are asked (TinyUSB's application class driver list): the
 * port supplies its table once after wsg_device_init(); a reset keeps it.
 * The table is the port's (static, const), the device keeps the pointer. */
void wsg_conn_set_drivers(wsg_device_t *dev, const wsg_proto_driver_t *const *drivers,
                          size_t count);
/* drv NULL: the first byte that arrives chooses the driver from the
 * device's table (wsg_conn_set_drivers); bytes no driver claims are dropped. */
void wsg_conn_open(wsg_conn_t *c, wsg_device_t *dev, const wsg_proto_driver_t *drv,
                   wsg_transport_t transport, const wsg_conn_io_t *io, void *io_ctx);
/* Returns the bytes it took: all of them under the "ideal" timing; under a
 * timing profile it stops after a whole request while that request waits
 * for the command processor, and the port keeps the rest (and stops
 * reading the socket) until the io's resume() hook. */
size_t wsg_conn_input(wsg_conn_t *c, const uint8_t *bytes, size_t len);
/* wsg_conn_input() for bytes the port kept back and feeds again after the
 * io's resume() hook: the same, but no new read for the connection
 * observers (they saw these bytes in the read that brought them). */
size_t wsg_conn_input_kept(wsg_conn_t *c, const uint8_t *bytes, size_t len);
/* A datagram ends any message it left open (UDP clients may omit the '\n'). */
void wsg_conn_end_datagram(wsg_conn_t *c);
/* True once the protocol said goodbye: the port closes after flushing. */
bool wsg_conn_wants_close(const wsg_conn_t *c);
/* True when the goodbye is the device's own: the stream sent a line only an
 * HTTP client sends (a web page's cross-protocol request), which closes it
 * unanswered, nothing it sent run (wsg_gcl_line_is_http()). */
bool wsg_conn_refused_http(const wsg_conn_t *c);
/* True once the protocol announced the connection's end: GCL's BYE (which
 * also wants the close) or the binary 0x07 (after which the client closes).
 * Closing it then is WSG_CLOSE_ANNOUNCED: no fault, no FAST STOP. */
bool wsg_conn_close_announced(const wsg_conn_t *c);
/* Detaches it from the device (no completion reaches it afterwards) and,
 * for a stream dropped without goodbye, raises FAST STOP when configured. */
void wsg_conn_close(wsg_conn_t *c, wsg_close_reason_t why);

bool wsg_conn_is_open(const wsg_conn_t *c);
uint64_t wsg_conn_id(const wsg_conn_t *c);
wsg_transport_t wsg_conn_transport(const wsg_conn_t *c);
wsg_device_t *wsg_conn_device(const wsg_conn_t *c);
/* Runs a motion, or the driver keeps it busy (subscriptions): a port must
 * not forget it to make room for another peer. */
bool wsg_conn_busy(const wsg_conn_t *c);
bool wsg_conn_owns_motion(const wsg_conn_t *c);
/* Whole messages (lines, frames) it has taken in so far, and whether it
 * holds part of the next one: a port tells a connection stuck in the middle
 * of a message from one that is quiet between commands. */
uint32_t wsg_conn_messages_in(const wsg_conn_t *c);
bool wsg_conn_partial_input(const wsg_conn_t *c);
/* The owner a driver starts long operations with: its done() event reaches
 * the driver's done(); closing the connection detaches it. */
wsg_owner_t *wsg_conn_owner(wsg_conn_t *c);

/* The port may interpose on its own output (the control channel's DELAY). */
void wsg_conn_get_io(const wsg_conn_t *c, const wsg_conn_io_t **io, void **io_ctx);
void wsg_conn_set_io(wsg_conn_t *c, const wsg_conn_io_t *io, void *io_ctx);
/* True while the connection's I/O holds replies back (its held() hook). */
bool wsg_conn_replies_held(const wsg_conn_t *c);

/* The device's open connections, oldest first (NULL at the end). */
wsg_conn_t *wsg_device_conn_first(wsg_device_t *dev);
wsg_conn_t *wsg_conn_next(const wsg_conn_t *c);
/* The open connection with this id, or NULL. */
wsg_conn_t *wsg_device_conn_by_id(wsg_device_t *dev, uint64_t id);

/* A message observer (trace, record, the web page's lines): a list node the
 * caller owns and fills in (callbacks may be NULL, ctx is theirs); the core
 * only links it (next), as lwIP's netif_add_ext_callback. Observers hear
 * every message of every connection of the device, in the order they were
 * added; a device without any pays one pointer test per message. Adding a
 * node that is already on the list does nothing; add and remove are
 * O(observers) and never allocate. Not from inside a callback. */
typedef struct wsg_conn_observer {
    void (*message_in)(void *ctx, const wsg_conn_t *c, const char *bytes, size_t len);
    void (*message_out)(void *ctx, const wsg_conn_t *c, const char *bytes, size_t len);
    void *ctx;
    struct wsg_conn_observer *next; /* the core's */
    /* Optional, after next so that older initialisers stay valid: bytes
     * arrived (one read, one datagram) before any message in them is taken
     * in, so whole messages seen before the next read arrived together;
     * and the connection closes (why; fast_stop: its close raised FAST
     * STOP), before it is detached, so its state can still be read. */
    void (*read)(void *ctx, const wsg_conn_t *c, const uint8_t *bytes, size_t len);
    void (*closed)(void *ctx, const wsg_conn_t *c, wsg_close_reason_t why, bool fast_stop);
} wsg_conn_observer_t;

void wsg_conn_add_observer(wsg_device_t *dev, wsg_conn_observer_t *node);
/* Unlinks the node; nothing when it is not on the device's list. */
void wsg_conn_remove_observer(wsg_device_t *dev, wsg_conn_observer_t *node);

#endif
