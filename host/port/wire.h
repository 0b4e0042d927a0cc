/* SPDX-License-Identifier: BSD-3-Clause */
/* Wire conditions applied where the servers write to and read from their
 * sockets (docs/network.md): a session's messages held back, split, joined,
 * lost or doubled on simulated time, as a real network would. A session
 * without conditions has no wire (NULL) and its port writes as always.
 *
 * What a wire holds leaves in the order it came, except datagrams that
 * reordering holds back: on TCP a later message never overtakes an earlier
 * one, and bytes leave in their order. Every random choice comes from the
 * session's own stream of the run's seed (wire_spec.h). */
#ifndef HOST_PORT_WIRE_H
#define HOST_PORT_WIRE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "list.h"
#include "wire_spec.h"
#include "wsg/wsg_conn.h"

typedef struct wire wire_t;

/* The wires of a fleet: the run's conditions (what a new session gets) and
 * the wires holding something, for their next instant. Zeroed, then
 * wire_set_init(). */
typedef struct {
    wire_spec_t all;        /* every session's, unless NET gave it its own */
    uint32_t run_seed;      /* --seed: a spec without seed= draws from it */
    list_t holding;         /* of wire_t with messages held */
    uint64_t due_us;        /* the earliest held message's instant, or UINT64_MAX */
    bool *deadline_lowered; /* set when due_us moves earlier (the owner asks again) */
} wire_set_t;

/* What a wire hands its port. deliver: bytes to write now (one write, or
 * one datagram); false when the port dropped them (an update over its
 * queue's room). reset: the connection is reset now (TCP). touch: the wire
 * must act earlier than its set knew (the port touches its device, whose
 * tick asks the servers' deadlines again: a query alone touches nothing). */
typedef struct {
    bool (*deliver)(void *ctx, const char *bytes, size_t len, wsg_msg_kind_t kind);
    void (*reset)(void *ctx);
    void (*touch)(void *ctx);
} wire_port_t;

/* What a wire did so far (NET? shows it; tests count it). */
typedef struct {
    unsigned long messages; /* handed to the wire */
    unsigned long writes;   /* writes or datagrams it made */
    unsigned long split;    /* messages that left in more than one write */
    unsigned long joined;   /* writes that carried more than one message */
    unsigned long lost_out, lost_in;
    unsigned long dup_out, dup_in;
    unsigned long reordered;
    bool reset; /* its reset came */
} wire_stats_t;

void wire_set_init(wire_set_t *set, bool *deadline_lowered);
/* The seed the wires of spec draw from: its seed= item, or the run's. */
uint64_t wire_set_seed(const wire_set_t *set, const wire_spec_t *spec);
/* A session's wire under spec (NULL: none needed, or out of memory).
 * stream: the session's number in the run (device and session id), for
 * its random choices; datagram: UDP. A TCP wire's reset comes within
 * spec->reset_us of now (the device time it opens at). */
wire_t *wire_open(wire_set_t *set, const wire_spec_t *spec, uint64_t stream, bool datagram,
                  const wire_port_t *port, void *ctx);
/* Closes a wire: what it holds is dropped (the session is gone). */
void wire_close(wire_t *w);
/* Hands what it holds to the port at once, then closes (conditions off). */
void wire_flush_close(wire_t *w);
/* A message the device sends, held and shaped by the conditions. */
void wire_send(wire_t *w, const char *bytes, size_t len, wsg_msg_kind_t kind);
/* How many copies of an arriving datagram the device gets: 0 (lost), 1
 * or 2 (doubled). */
unsigned wire_receive_copies(wire_t *w);
/* The wire holds messages not yet written. */
bool wire_holding(const wire_t *w);
const wire_spec_t *wire_spec(const wire_t *w);
const wire_stats_t *wire_stats(const wire_t *w);
/* Writes everything due by now, and resets connections whose reset came. */
void wire_run_due(wire_set_t *set, uint64_t now);
/* The earliest instant a wire must act, or UINT64_MAX. */
static inline uint64_t wire_next_us(const wire_set_t *set)
{
    return set->due_us;
}

#endif
