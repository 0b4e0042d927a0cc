/* SPDX-License-Identifier: BSD-3-Clause */
/* A queue of real deadlines, sorted, intrusive: the elements live in their
 * owners (an AUTOSEND subscription inside its connection), the queue only
 * links them. Insertion walks the list (there are a handful of distinct
 * periods per connection); the next deadline is the head; running what is
 * due touches only what is due. */
#ifndef WSG_TIMER_H
#define WSG_TIMER_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

typedef struct wsg_timer {
    uint64_t due_us;
    void (*fire)(struct wsg_timer *timer, uint64_t now_us);
    struct wsg_timer *next;
    bool queued;
} wsg_timer_t;

typedef struct {
    wsg_timer_t *head;
    /* the due timers wsg_timer_run_due() has taken off and not fired yet:
     * one may cancel or reschedule another (a served request starting a
     * stream) */
    wsg_timer_t *firing;
} wsg_timer_queue_t;

void wsg_timer_queue_init(wsg_timer_queue_t *q);
/* (Re)schedules t at due_us; equal deadlines keep their insertion order. */
void wsg_timer_schedule(wsg_timer_queue_t *q, wsg_timer_t *t, uint64_t due_us);
void wsg_timer_cancel(wsg_timer_queue_t *q, wsg_timer_t *t);
static inline uint64_t wsg_timer_next_due(const wsg_timer_queue_t *q)
{
    return q->head != NULL ? q->head->due_us : UINT64_MAX;
}
/* Fires every timer due at now_us, in deadline order, each at most once per
 * call (a timer that reschedules itself into the past waits for the next). */
void wsg_timer_run_due(wsg_timer_queue_t *q, uint64_t now_us);

#endif
