/* SPDX-License-Identifier: BSD-3-Clause */
/* An interpreter's allocator (script_internal.h): every block it hands to
 * Lua is on a list, so that an interpreter the watchdog stopped can be
 * dropped without running anything of it (lua_close would run its
 * finalizers and walk a state left mid-change); the per-interpreter cap
 * and the process's budget (script_guard.h) both count its bytes, the
 * blocks' list links included. */
#include <stdalign.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>

#include "script_guard.h"
#include "script_internal.h"

/* The link in front of each block; its size keeps Lua's alignment. */
struct script_block {
    alignas(max_align_t) struct script_block *prev;
    struct script_block *next;
};
typedef struct script_block block_t;

static void link_block(script_t *s, block_t *b, block_t *prev, block_t *next)
{
    b->prev = prev;
    b->next = next;
    if (prev != NULL) {
        prev->next = b;
    } else {
        s->blocks = b;
    }
    if (next != NULL) {
        next->prev = b;
    }
}

static void unlink_block(script_t *s, const block_t *b)
{
    if (b->prev != NULL) {
        b->prev->next = b->next;
    } else {
        s->blocks = b->next;
    }
    if (b->next != NULL) {
        b->next->prev = b->prev;
    }
}

/* What a block of size bytes for Lua costs. */
static size_t footprint(size_t size)
{
    return size + sizeof(block_t);
}

static void release(script_t *s, size_t bytes)
{
    s->memory -= bytes;
    script_guard_release(s->guard, bytes);
}

/* Room for `more` bytes: within the interpreter's cap and the process's
 * budget; *s->refused says which one said no. */
static bool reserve(script_t *s, size_t more)
{
    if (more > SCRIPT_MEMORY_CAP - s->memory) {
        s->refused = SCRIPT_REFUSED_CAP;
        return false;
    }
    if (!script_guard_reserve(s->guard, more)) {
        s->refused = SCRIPT_REFUSED_BUDGET;
        return false;
    }
    s->memory += more;
    return true;
}

static void free_block(script_t *s, block_t *b, size_t size)
{
    unlink_block(s, b);
    script_guard_enter_host(s->guard);
    free(b);
    script_guard_leave_host(s->guard);
    release(s, footprint(size));
}

/* Grows or shrinks (or makes, b NULL) a block; NULL when refused, the old
 * block then unchanged and still listed. */
static void *resize_block(script_t *s, block_t *b, size_t old, size_t size)
{
    size_t had = b != NULL ? footprint(old) : 0u;
    if (size > SIZE_MAX - sizeof(block_t) ||
        (footprint(size) > had && !reserve(s, footprint(size) - had))) {
        return NULL;
    }
    block_t *prev = b != NULL ? b->prev : NULL;
    block_t *next = b != NULL ? b->next : s->blocks;
    script_guard_enter_host(s->guard);
    block_t *moved = realloc(b, footprint(size));
    script_guard_leave_host(s->guard);
    if (moved == NULL) {
        if (footprint(size) > had) {
            release(s, footprint(size) - had);
        }
        return NULL;
    }
    link_block(s, moved, prev, next);
    if (footprint(size) < had) {
        release(s, had - footprint(size));
    }
    return moved + 1;
}

void *script_heap_alloc(void *ud, void *ptr, size_t osize, size_t nsize)
{
    script_t *s = ud;
    script_guard_safe_point(s->guard);
    block_t *b = ptr != NULL ? (block_t *)ptr - 1 : NULL;
    if (nsize == 0) {
        if (b != NULL) {
            free_block(s, b, osize);
        }
        return NULL;
    }
    void *out = resize_block(s, b, ptr != NULL ? osize : 0u, nsize);
    script_guard_safe_point(s->guard); /* the block is listed: dropping it is fine */
    return out;
}

void script_heap_drop(script_t *s)
{
    while (s->blocks != NULL) {
        block_t *b = s->blocks;
        s->blocks = b->next;
        free(b);
    }
    script_guard_release(s->guard, s->memory);
    s->memory = 0;
}
