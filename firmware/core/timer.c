/* SPDX-License-Identifier: BSD-3-Clause */
/* The timer queue (priv/timer.h). */
#include "priv/timer.h"

#include <stddef.h>

void wsg_timer_queue_init(wsg_timer_queue_t *q)
{
    q->head = NULL;
    q->firing = NULL;
}

static bool unlink_from(wsg_timer_t **link, const wsg_timer_t *t)
{
    for (; *link != NULL; link = &(*link)->next) {
        if (*link == t) {
            *link = t->next;
            return true;
        }
    }
    return false;
}

void wsg_timer_cancel(wsg_timer_queue_t *q, wsg_timer_t *t)
{
    if (!t->queued) {
        return;
    }
    if (!unlink_from(&q->head, t)) {
        (void)unlink_from(&q->firing, t); /* due, not fired yet: it fires no more */
    }
    t->next = NULL;
    t->queued = false;
}

void wsg_timer_schedule(wsg_timer_queue_t *q, wsg_timer_t *t, uint64_t due_us)
{
    wsg_timer_cancel(q, t);
    wsg_timer_t **link = &q->head;
    while (*link != NULL && (*link)->due_us <= due_us) {
        link = &(*link)->next;
    }
    t->due_us = due_us;
    t->next = *link;
    t->queued = true;
    *link = t;
}

void wsg_timer_run_due(wsg_timer_queue_t *q, uint64_t now_us)
{
    /* detach the due prefix first, so that rescheduling cannot loop; a
     * fire that cancels or reschedules one of them takes it off there */
    wsg_timer_t **tail = &q->firing;
    while (q->head != NULL && q->head->due_us <= now_us) {
        wsg_timer_t *t = q->head;
        q->head = t->next;
        t->next = NULL;
        *tail = t;
        tail = &t->next;
    }
    while (q->firing != NULL) {
        wsg_timer_t *t = q->firing;
        q->firing = t->next;
        t->next = NULL;
        t->queued = false;
        t->fire(t, now_us);
    }
}
