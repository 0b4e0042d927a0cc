/* SPDX-License-Identifier: BSD-3-Clause */
#include "plant_socket.h"

#include <errno.h>
#include <poll.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <time.h>
#include <unistd.h>

#include "hal_log.h"
#include "log.h"
#include "plant_wire.h"

#define FAULT_MAX 200u

typedef struct {
    int fd; /* -1: not connected (a fault) */
    char path[sizeof(((struct sockaddr_un *)0)->sun_path)];
    unsigned timeout_ms;
    float stroke_mm;
    plant_wire_hello_t hello;
    plant_sample_t last; /* the last good sample: a lost plant's jaws stand there */
    char fault[FAULT_MAX];
    uint8_t buf[PLANT_WIRE_HEADER + PLANT_WIRE_PAYLOAD_MAX];
} socket_plant_t;

static uint64_t monotonic_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (uint64_t)ts.tv_sec * 1000u + (uint64_t)ts.tv_nsec / 1000000u;
}

/* The plant is lost: why, logged once; the socket closed (what it still
 * sends would be out of step). */
static void lose(socket_plant_t *sp, const char *what, const char *why)
{
    if (sp->fd >= 0) {
        close(sp->fd);
        sp->fd = -1;
    }
    snprintf(sp->fault, sizeof(sp->fault), "plant at %s: %s: %s", sp->path, what, why);
    host_logf(HAL_LOG_ERROR, "%s", sp->fault);
}

/* Waits for events on the socket until the deadline: false when it passed. */
static bool wait_for(socket_plant_t *sp, short events, uint64_t deadline_ms)
{
    for (;;) {
        uint64_t now = monotonic_ms();
        if (now >= deadline_ms) {
            return false;
        }
        struct pollfd pfd = {sp->fd, events, 0};
        int n = poll(&pfd, 1, (int)(deadline_ms - now));
        if (n > 0) {
            return true;
        }
        if (n < 0 && errno != EINTR) {
            return false;
        }
    }
}

/* Moves len bytes out (send) or in (recv) by the deadline: NULL, or why not. */
static const char *transfer(socket_plant_t *sp, uint8_t *at, size_t len, bool out,
                            uint64_t deadline_ms)
{
    size_t done = 0u;
    while (done < len) {
        if (!wait_for(sp, out ? POLLOUT : POLLIN, deadline_ms)) {
            return "no answer in time";
        }
        ssize_t n = out ? send(sp->fd, at + done, len - done, MSG_NOSIGNAL | MSG_DONTWAIT)
                        : recv(sp->fd, at + done, len - done, MSG_DONTWAIT);
        if (n == 0) {
            return "the plant closed the connection";
        }
        if (n < 0 && errno != EAGAIN && errno != EINTR) {
            return strerror(errno);
        }
        done += n > 0 ? (size_t)n : 0u;
    }
    return NULL;
}

/* One request and its reply (lock-step): the reply's payload in sp->buf
 * past the header; false when the plant is lost. */
static bool exchange(socket_plant_t *sp, plant_msg_t type, const uint8_t *payload, size_t len,
                     plant_wire_header_t *reply)
{
    static const char *const names[] = {"",       "HELLO", "RESET",    "STEP",
                                        "BODIES", "BODY",  "CONTACTS", "SET"};
    if (sp->fd < 0) {
        return false;
    }
    uint64_t deadline = monotonic_ms() + sp->timeout_ms;
    size_t n = plant_wire_request(sp->buf, type, payload, len);
    const char *why = transfer(sp, sp->buf, n, true, deadline);
    why = why != NULL ? why : transfer(sp, sp->buf, PLANT_WIRE_HEADER, false, deadline);
    why = why != NULL ? why : plant_wire_header(sp->buf, type, reply);
    uint8_t *body = sp->buf + PLANT_WIRE_HEADER;
    why = why != NULL ? why : transfer(sp, body, reply->length, false, deadline);
    if (why != NULL) {
        lose(sp, names[type], why);
        return false;
    }
    return true;
}

static bool shake_hands(socket_plant_t *sp)
{
    uint8_t payload[PLANT_WIRE_HELLO_REQ];
    plant_wire_put_f32(payload, sp->stroke_mm);
    plant_wire_put_f32(payload + 4, sp->last.width_mm);
    plant_wire_header_t reply;
    if (!exchange(sp, PLANT_MSG_HELLO, payload, sizeof(payload), &reply)) {
        return false;
    }
    const char *why = plant_wire_hello(sp->buf + PLANT_WIRE_HEADER, reply.length, &sp->hello);
    uint32_t ts = sp->hello.timestep_us;
    if (why == NULL && (ts == 0u || PHYSICS_EXCHANGE_US % ts != 0u)) {
        why = "its timestep does not divide the device's 1 ms exchange";
    }
    if (why != NULL) {
        lose(sp, "HELLO", why);
        return false;
    }
    return true;
}

static bool connect_plant(socket_plant_t *sp)
{
    struct sockaddr_un addr = {.sun_family = AF_UNIX};
    memcpy(addr.sun_path, sp->path, sizeof(sp->path));
    /* non-blocking: a plant whose queue of connections is full refuses at
     * once (EAGAIN) instead of holding the loop */
    sp->fd = socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC | SOCK_NONBLOCK, 0);
    if (sp->fd < 0 || connect(sp->fd, (struct sockaddr *)&addr, sizeof(addr)) != 0) {
        lose(sp, "connect", strerror(errno));
        return false;
    }
    sp->fault[0] = '\0';
    return shake_hands(sp);
}

static uint32_t sock_timestep_us(void *ctx)
{
    const socket_plant_t *sp = ctx;
    return sp->hello.timestep_us;
}

static void sock_step(void *ctx, const plant_drive_t *drive, uint32_t dt_us, plant_sample_t *out)
{
    socket_plant_t *sp = ctx;
    uint8_t payload[PLANT_WIRE_STEP_REQ];
    plant_wire_step_payload(payload, drive, dt_us);
    plant_wire_header_t reply;
    plant_sample_t sample;
    if (exchange(sp, PLANT_MSG_STEP, payload, sizeof(payload), &reply)) {
        const char *why = plant_wire_sample(sp->buf + PLANT_WIRE_HEADER, reply.length, &sample);
        if (why == NULL) {
            sample.fault = false;
            sp->last = sample;
            *out = sample;
            return;
        }
        lose(sp, "STEP", why);
    }
    /* lost: the jaws stand where they were, the motor exerts nothing */
    sp->last.time_us += dt_us;
    sp->last.velocity_mm_s = 0.0f;
    sp->last.motor_force_n = 0.0f;
    sp->last.quiet = true;
    sp->last.fault = true;
    *out = sp->last;
}

static void sock_reset(void *ctx, float width_mm)
{
    socket_plant_t *sp = ctx;
    memset(&sp->last, 0, sizeof(sp->last));
    sp->last.width_mm = width_mm;
    if (sp->fd < 0 && !connect_plant(sp)) { /* a lost plant: try again */
        sp->last.fault = true;
        return;
    }
    uint8_t payload[PLANT_WIRE_RESET_REQ];
    plant_wire_put_f32(payload, width_mm);
    plant_wire_header_t reply;
    sp->last.fault = !exchange(sp, PLANT_MSG_RESET, payload, sizeof(payload), &reply);
}

static unsigned sock_body_count(void *ctx)
{
    socket_plant_t *sp = ctx;
    plant_wire_header_t reply;
    unsigned count = 0u;
    if ((sp->hello.features & PLANT_FEATURE_BODIES) == 0u ||
        !exchange(sp, PLANT_MSG_BODIES, NULL, 0u, &reply) || reply.status != PLANT_OK) {
        return 0u;
    }
    const char *why = plant_wire_bodies(sp->buf + PLANT_WIRE_HEADER, reply.length, &count);
    if (why != NULL) {
        lose(sp, "BODIES", why);
    }
    return count;
}

static bool sock_body(void *ctx, unsigned index, plant_body_t *out)
{
    socket_plant_t *sp = ctx;
    uint8_t payload[PLANT_WIRE_BODY_REQ];
    plant_wire_put_u32(payload, index);
    plant_wire_header_t reply;
    if ((sp->hello.features & PLANT_FEATURE_BODIES) == 0u ||
        !exchange(sp, PLANT_MSG_BODY, payload, sizeof(payload), &reply) ||
        reply.status != PLANT_OK) {
        return false;
    }
    const char *why = plant_wire_body(sp->buf + PLANT_WIRE_HEADER, reply.length, out);
    if (why != NULL) {
        lose(sp, "BODY", why);
    }
    return why == NULL;
}

static unsigned sock_contacts(void *ctx, plant_contact_t *out, unsigned cap)
{
    socket_plant_t *sp = ctx;
    unsigned asked = cap < PLANT_WIRE_CONTACTS_MAX ? cap : PLANT_WIRE_CONTACTS_MAX;
    uint8_t payload[PLANT_WIRE_CONTACTS_REQ];
    plant_wire_put_u32(payload, asked);
    plant_wire_header_t reply;
    unsigned total = 0u;
    if ((sp->hello.features & PLANT_FEATURE_CONTACTS) == 0u ||
        !exchange(sp, PLANT_MSG_CONTACTS, payload, sizeof(payload), &reply) ||
        reply.status != PLANT_OK) {
        return 0u;
    }
    const char *why =
        plant_wire_contacts(sp->buf + PLANT_WIRE_HEADER, reply.length, out, asked, &total);
    if (why != NULL) {
        lose(sp, "CONTACTS", why);
        return 0u;
    }
    return total;
}

static plant_err_t sock_set(void *ctx, unsigned index, plant_set_t what, const double *value)
{
    socket_plant_t *sp = ctx;
    uint8_t payload[PLANT_WIRE_SET_REQ];
    plant_wire_set_payload(payload, index, what, value);
    plant_wire_header_t reply;
    if ((sp->hello.features & PLANT_FEATURE_SET) == 0u) {
        return PLANT_ERR_UNSUPPORTED;
    }
    if (!exchange(sp, PLANT_MSG_SET, payload, sizeof(payload), &reply)) {
        return PLANT_ERR_UNSUPPORTED;
    }
    return (plant_err_t)reply.status;
}

static void sock_destroy(void *ctx)
{
    socket_plant_t *sp = ctx;
    if (sp->fd >= 0) {
        close(sp->fd);
    }
    free(sp);
}

static const plant_ops_t socket_ops = {
    .name = "socket",
    .timestep_us = sock_timestep_us,
    .step = sock_step,
    .reset = sock_reset,
    .body_count = sock_body_count,
    .body = sock_body,
    .contacts = sock_contacts,
    .set = sock_set,
    .destroy = sock_destroy,
};

bool plant_socket_open(plant_t *plant, const char *path, unsigned timeout_ms, float stroke_mm,
                       float width_mm, char *why, size_t cap)
{
    socket_plant_t *sp = calloc(1u, sizeof(*sp));
    if (sp == NULL || strlen(path) >= sizeof(sp->path) || path[0] == '\0') {
        snprintf(why, cap, sp == NULL ? "out of memory" : "socket path empty or too long: %s",
                 path);
        free(sp);
        return false;
    }
    sp->fd = -1;
    snprintf(sp->path, sizeof(sp->path), "%s", path);
    sp->timeout_ms = timeout_ms;
    sp->stroke_mm = stroke_mm;
    sp->last.width_mm = width_mm;
    if (!connect_plant(sp)) {
        snprintf(why, cap, "%s", sp->fault);
        sock_destroy(sp);
        return false;
    }
    *plant = (plant_t){&socket_ops, sp};
    return true;
}

const char *plant_socket_fault(const plant_t *plant)
{
    if (plant->ops != &socket_ops) {
        return NULL;
    }
    const socket_plant_t *sp = plant->ctx;
    return sp->fd < 0 ? sp->fault : NULL;
}

physics_world_t *plant_socket_world_open(const char *path, unsigned timeout_ms, float stroke_mm,
                                         float emergency_accel_mm_s2, uint64_t now_us, char *why,
                                         size_t cap)
{
    plant_t plant;
    if (!plant_socket_open(&plant, path, timeout_ms, stroke_mm, stroke_mm / 2.0f, why, cap)) {
        return NULL;
    }
    return physics_world_new(plant, stroke_mm, emergency_accel_mm_s2, now_us, why, cap);
}
