/* SPDX-License-Identifier: BSD-3-Clause */
/* The timer queue (priv/timer.h). */
#include "priv/timer.h"

#include <stddef.h>

void wsg_timer_queue_init(wsg_timer_queue_t *q)
{
    q->head = NULL;
}

void wsg_timer_cancel(wsg_timer_queue_t *q, wsg_timer_t *t)
{
    if (!t->queued) {
        return;
    }
    for (wsg_timer_t **link = &q->head; *link != NULL; link = &(*link)->next) {
        if (*link == t) {
            *link = t->next;
            break;
        }
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
    /* detach the due prefix first, so that rescheduling cannot loop */
    wsg_timer_t *due = NULL;
    wsg_timer_t **tail = &due;
    while (q->head != NULL && q->head->due_us <= now_us) {
        wsg_timer_t *t = q->head;
        q->head = t->next;
        t->next = NULL;
        *tail = t;
        tail = &t->next;
    }
    while (due != NULL) {
        wsg_timer_t *t = due;
        due = t->next;
        t->next = NULL;
        t->queued = false;
        t->fire(t, now_us);
    }
}
