/* SPDX-License-Identifier: BSD-3-Clause */
/* Intrusive doubly linked lists: the element holds its node (list_node_t),
 * the list holds its ends (list_t), so linking allocates nothing and
 * unlinking takes O(1) without a search, as the Linux kernel's list_head.
 * Unlike list_head the ends are NULL-terminated: a zeroed list_t is an
 * empty list, as a zeroed (calloc'd) owner expects. An element on several
 * lists has a node per list. */
#ifndef HOST_LIST_H
#define HOST_LIST_H

#include <stdbool.h>
#include <stddef.h>

typedef struct list_node {
    struct list_node *prev, *next;
} list_node_t;

/* Zeroed: empty. */
typedef struct {
    list_node_t *first, *last;
} list_t;

/* The element of type that holds node as its member. */
#define LIST_ITEM(node, type, member) ((type *)(void *)((char *)(node)-offsetof(type, member)))

/* Every node from the first on; the body must not unlink node. */
#define LIST_EACH(node, list)                                                                      \
    for (list_node_t *node = (list)->first; node != NULL; node = node->next)

/* The same, for a body that may unlink node (and nothing else). */
#define LIST_EACH_SAFE(node, list)                                                                 \
    for (list_node_t *node = (list)->first, *node##_next = node != NULL ? node->next : NULL;       \
         node != NULL; node = node##_next, node##_next = node != NULL ? node->next : NULL)

static inline bool list_empty(const list_t *list)
{
    return list->first == NULL;
}

static inline void list_push_back(list_t *list, list_node_t *node)
{
    node->prev = list->last;
    node->next = NULL;
    if (list->last != NULL) {
        list->last->next = node;
    } else {
        list->first = node;
    }
    list->last = node;
}

static inline void list_push_front(list_t *list, list_node_t *node)
{
    node->prev = NULL;
    node->next = list->first;
    if (list->first != NULL) {
        list->first->prev = node;
    } else {
        list->last = node;
    }
    list->first = node;
}

/* node must be on list. */
static inline void list_remove(list_t *list, list_node_t *node)
{
    if (node->prev != NULL) {
        node->prev->next = node->next;
    } else {
        list->first = node->next;
    }
    if (node->next != NULL) {
        node->next->prev = node->prev;
    } else {
        list->last = node->prev;
    }
    node->prev = node->next = NULL;
}

/* The first node, unlinked; NULL when the list is empty. */
static inline list_node_t *list_pop_front(list_t *list)
{
    list_node_t *node = list->first;
    if (node != NULL) {
        list_remove(list, node);
    }
    return node;
}

#endif
