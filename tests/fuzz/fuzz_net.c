/* SPDX-License-Identifier: BSD-3-Clause */
/* libFuzzer target: wire conditions (host/os/wire_spec.c, the text of
 * --net, [net] conditions and the control channel's NET) and the wire that
 * applies them (host/port/wire.c). The input's first line is a condition
 * text, the rest the bytes a device sends, cut into messages at each '\n'.
 *   - a text that is refused leaves the spec as it was and gives a reason;
 *   - an accepted one, written back (wire_spec_format), reads back to the
 *     same text;
 *   - over a TCP wire under it, on a paused clock stepped until nothing is
 *     held, every byte arrives once and in order, unless the reset came. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "clock.h"
#include "wire.h"
#include "wire_spec.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

#define TEXT_MAX 256
#define OUT_MAX (64u * 1024u)

typedef struct {
    char out[OUT_MAX];
    size_t len;
    bool reset;
} port_t;

static bool deliver(void *ctx, const char *bytes, size_t len, wsg_msg_kind_t kind)
{
    port_t *p = ctx;
    (void)kind;
    if (p->len + len > sizeof(p->out)) {
        abort();
    }
    memcpy(p->out + p->len, bytes, len);
    p->len += len;
    return true;
}

static void reset(void *ctx)
{
    ((port_t *)ctx)->reset = true;
}

static void touch(void *ctx)
{
    (void)ctx;
}

static const wire_port_t fuzz_port = {.deliver = deliver, .reset = reset, .touch = touch};

static void check_text(const wire_spec_t *spec)
{
    char text[WIRE_SPEC_TEXT_MAX], again[WIRE_SPEC_TEXT_MAX], why[160];
    wire_spec_format(spec, text, sizeof(text));
    wire_spec_t reread = *spec;
    if (!wire_spec_parse(&reread, text, why, sizeof(why))) {
        fprintf(stderr, "fuzz_net: %s written back is refused: %s\n", text, why);
        abort();
    }
    wire_spec_format(&reread, again, sizeof(again));
    if (strcmp(text, again) != 0) {
        fprintf(stderr, "fuzz_net: %s reads back as %s\n", text, again);
        abort();
    }
}

/* The messages through a TCP wire; every byte once, in order. */
static void check_stream(const wire_spec_t *spec, const uint8_t *bytes, size_t size)
{
    static port_t port;
    simclock_t clock;
    wire_set_t set;
    memset(&port, 0, sizeof(port));
    simclock_init(&clock);
    simclock_start_paused(&clock);
    wire_set_init(&set, NULL);
    wire_t *w = wire_open(&set, spec, 1u, false, &fuzz_port, &port);
    if (w == NULL) {
        simclock_fini(&clock);
        return;
    }
    size_t at = 0;
    while (at < size && !port.reset) {
        const uint8_t *end = memchr(bytes + at, '\n', size - at);
        size_t len = end != NULL ? (size_t)(end - (bytes + at)) + 1u : size - at;
        wire_send(w, (const char *)bytes + at, len, WSG_MSG_REPLY);
        at += len;
        simclock_step(&clock, 500u);
        simclock_advance_device(&clock, simclock_now_us(&clock));
        wire_run_due(&set, clock.device_us);
    }
    while (wire_next_us(&set) != UINT64_MAX && !port.reset) {
        simclock_step(&clock, wire_next_us(&set) - clock.device_us);
        simclock_advance_device(&clock, wire_next_us(&set));
        wire_run_due(&set, clock.device_us);
    }
    if (!port.reset && (port.len != size || memcmp(port.out, bytes, size) != 0)) {
        fprintf(stderr, "fuzz_net: %zu bytes sent, %zu arrived or out of order\n", size, port.len);
        abort();
    }
    wire_close(w);
    simclock_fini(&clock);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    const uint8_t *nl = memchr(data, '\n', size);
    size_t text_len = nl != NULL ? (size_t)(nl - data) : size;
    char text[TEXT_MAX], why[160];
    if (text_len >= sizeof(text) || memchr(data, '\0', text_len) != NULL) {
        return 0;
    }
    memcpy(text, data, text_len);
    text[text_len] = '\0';
    wire_spec_t spec = {0}, before;
    spec.seed = 3;
    before = spec;
    if (!wire_spec_parse(&spec, text, why, sizeof(why))) {
        if (memcmp(&spec, &before, sizeof(spec)) != 0 || why[0] == '\0') {
            abort();
        }
        return 0;
    }
    check_text(&spec);
    size_t body = nl != NULL ? size - text_len - 1u : 0u;
    check_stream(&spec, nl != NULL ? nl + 1 : data, body < OUT_MAX / 2 ? body : OUT_MAX / 2);
    return 0;
}
