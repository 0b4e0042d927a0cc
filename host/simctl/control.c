/* SPDX-License-Identifier: BSD-3-Clause */
#include "control.h"

#include <errno.h>
#include <poll.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <unistd.h>

#include "commands.h"
#include "listener.h"
#include "log.h"
#include "loop.h"
#include "net.h"
#include "wsg/wsg_outq.h"
#include "scheduler.h"
#include "wsg/gcl_linebuf.h"

#define CONTROL_CLIENTS_MAX 8
/* Replies wait here for a slow reader. A command runs only while less than
 * CONTROL_OUTQ_LOW is queued, so the queue always has room for the largest
 * reply (a STATE? of every session is about 70 KB) and a client that sends
 * faster than it reads is slowed down, not cut off. */
#define CONTROL_OUTQ_BYTES (512u * 1024u)
#define CONTROL_OUTQ_LOW (64u * 1024u)
#define OUTQ_RECORD_MAX 0xffffu /* wsg_outq_offer() takes at most this per call */
#define READ_CHUNK 4096
#define DEFAULT_ADDR "127.0.0.1"

typedef struct {
    simctl_t *ctl;
    bool in_use;
    bool closing; /* BYE answered: close once flushed */
    bool dead;    /* the peer went away or failed: close now */
    bool eof;     /* the peer sent everything: answer it, then close */
    int fd;
    unsigned number; /* ctl<number> in logs and records */
    unsigned device; /* the device its commands address (DEVICE=) */
    gcl_linebuf_t input;
    uint8_t pending[READ_CHUNK]; /* received, not yet run (while a STEP runs) */
    size_t pending_len;
    size_t pending_at;
    wsg_outq_t outq;
} control_client_t;

struct simctl {
    simctl_sim_t sim;               /* first: the inline accessors of control.h */
    simctl_due_hook_t scenario_due; /* the scenario's commands, run by the scheduler */
    listener_t listener;
    const char *addr;
    unsigned connections;
    control_client_t *stepper; /* waits for the reply of its STEP */
    bool step_ended;           /* a STEP ended: its reply and the queued commands wait */
    control_client_t clients[CONTROL_CLIENTS_MAX];
    char out_line[OUTQ_RECORD_MAX]; /* one queued record on its way to send() */
};

/* The scenario's lines run as the channel's do, each recorded (--record)
 * as a scenario's. */
static bool scenario_check(void *ctx, const char *line, size_t len, char *why, size_t cap)
{
    return simctl_check(ctx, line, len, true, why, cap);
}

static char *scenario_run(void *ctx, const char *line, size_t len)
{
    simctl_t *ctl = ctx;
    record_control(ctl->sim.record, "scn", '<', line, len);
    char *reply = simctl_exec(ctl, line, len, NULL, NULL);
    record_control(ctl->sim.record, "scn", '>', reply, strlen(reply));
    return reply;
}

static uint64_t scenario_due_next_us(void *ctx)
{
    return scenario_next_us(ctx);
}

static unsigned scenario_due_run(void *ctx, uint64_t now_us, unsigned max)
{
    return scenario_run_due(ctx, now_us, max);
}

simctl_t *simctl_create(void)
{
    simctl_t *ctl = calloc(1, sizeof(*ctl));
    if (ctl == NULL) {
        return NULL;
    }
    simctl_sim_t *sim = &ctl->sim;
    simclock_init(&sim->clock);
    scenario_init(&sim->scenario, (scenario_commands_t){scenario_check, scenario_run, ctl});
    simctl_scheduler_init(&sim->sched, &sim->clock);
    ctl->scenario_due = (simctl_due_hook_t){scenario_due_next_us, scenario_due_run, &sim->scenario};
    simctl_scheduler_set_due_hook(&sim->sched, &ctl->scenario_due);
    simctl_faults_init(&sim->faults);
    ctl->listener.fd = -1;
    for (unsigned i = 0; i < CONTROL_CLIENTS_MAX; i++) {
        ctl->clients[i].ctl = ctl;
    }
    return ctl;
}

void simctl_destroy(simctl_t *ctl)
{
    if (ctl == NULL) {
        return;
    }
    simctl_stop(ctl);
    scenario_unload(&ctl->sim.scenario);
    simctl_faults_release(&ctl->sim.faults);
    simclock_fini(&ctl->sim.clock);
    free(ctl);
}

void simctl_set_fleet(simctl_t *ctl, struct fleet *fleet)
{
    ctl->sim.fleet = fleet;
    ctl->sim.sched.fleet = fleet;
}

static void channel_name(const control_client_t *c, char *out, size_t cap)
{
    snprintf(out, cap, "ctl%u", c->number);
}

static void close_client(control_client_t *c)
{
    simctl_t *ctl = c->ctl;
    if (ctl->stepper == c) {
        ctl->stepper = NULL; /* the STEP itself runs on */
    }
    loop_unwatch(ctl->listener.loop, c->fd);
    close(c->fd);
    listener_fd_freed(&ctl->listener);
    free(c->outq.ring);
    c->in_use = false;
    host_logf(HAL_LOG_INFO, "control ctl%u: closed", c->number);
}

static bool input_left(const control_client_t *c)
{
    return c->pending_at < c->pending_len;
}

/* POLLIN once the received bytes have run; POLLOUT while replies wait. */
static void update_events(control_client_t *c)
{
    bool want_input = !c->eof && !input_left(c);
    bool want_output = !wsg_outq_empty(&c->outq);
    loop_set_events(c->ctl->listener.loop, c->fd,
                    (short)((want_input ? POLLIN : 0) | (want_output ? POLLOUT : 0)));
}

static void flush(control_client_t *c)
{
    char *line = c->ctl->out_line;
    while (!wsg_outq_empty(&c->outq)) {
        size_t len = wsg_outq_peek(&c->outq, line, OUTQ_RECORD_MAX);
        ssize_t sent = send(c->fd, line, len, MSG_NOSIGNAL | MSG_DONTWAIT);
        if (sent < 0 && (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR)) {
            break;
        }
        if (sent < 0) {
            c->dead = true;
            break;
        }
        wsg_outq_consume(&c->outq, (size_t)sent);
        if ((size_t)sent < len) {
            break;
        }
    }
    update_events(c);
}

/* Queues reply + "\n" in pieces outq takes (a short reply is one piece, so
 * one send()); a reply of any size fits while commands run only with
 * CONTROL_OUTQ_LOW or less queued. */
static bool queue_reply(control_client_t *c, const char *reply)
{
    size_t len = strlen(reply) + 1;
    char *line = malloc(len);
    if (line == NULL || len > c->outq.cap - wsg_outq_used(&c->outq) - CONTROL_OUTQ_LOW) {
        free(line);
        return false;
    }
    memcpy(line, reply, len - 1);
    line[len - 1] = '\n';
    bool queued = true;
    for (size_t at = 0; queued && at < len;) {
        size_t n = len - at < OUTQ_RECORD_MAX ? len - at : OUTQ_RECORD_MAX;
        queued = wsg_outq_offer(&c->outq, line + at, n, WSG_MSG_REPLY) == WSG_OUTQ_QUEUED;
        at += n;
    }
    free(line);
    return queued;
}

static void send_reply(control_client_t *c, const char *reply)
{
    if (!queue_reply(c, reply)) {
        host_logf(HAL_LOG_WARN, "control ctl%u: reply too long or not read; closing", c->number);
        c->dead = true;
    }
    flush(c);
}

static void record_and_send(control_client_t *c, const char *reply)
{
    char channel[16];
    channel_name(c, channel, sizeof(channel));
    record_control(c->ctl->sim.record, channel, '>', reply, strlen(reply));
    send_reply(c, reply);
}

/* A browser can be made to send a cross-site POST to any port, and the
 * lines of its body would run here as commands. As Redis does when a
 * command reads "POST" or "Host:", a line that only an HTTP client sends
 * (no control command looks like one: a name is followed by '(', '?' or
 * '=') closes the connection at once, before anything it sent runs. */
static bool refuse_http(control_client_t *c)
{
    const char *line = c->input.text;
    if (!wsg_gcl_line_is_http(line)) {
        return false;
    }
    host_log_peer(HAL_LOG_WARN,
                  "control ctl%u: an HTTP request (a web page's cross-protocol request?); "
                  "closing without running it",
                  c->number);
    c->dead = true;
    return true;
}

static void handle_line(control_client_t *c)
{
    const gcl_linebuf_t *lb = &c->input;
    char channel[16];
    channel_name(c, channel, sizeof(channel));
    if (wsg_gcl_linebuf_status(lb) == GCL_LINE_OK && strspn(lb->text, " \t") == lb->len) {
        return; /* blank line */
    }
    if (refuse_http(c)) {
        return;
    }
    record_control(c->ctl->sim.record, channel, '<', lb->text, lb->len);
    char *reply = NULL;
    simctl_outcome_t outcome = {false, false};
    if (wsg_gcl_linebuf_status(lb) != GCL_LINE_OK) {
        reply = strdup("ERR ? 15 line too long or with control bytes");
    } else {
        reply = simctl_exec(c->ctl, lb->text, lb->len, &c->device, &outcome);
    }
    if (outcome.deferred) {
        c->ctl->stepper = c; /* the reply comes when the STEP has run */
        return;
    }
    if (reply == NULL) {
        return;
    }
    record_and_send(c, reply);
    free(reply);
    c->closing = c->closing || outcome.close;
}

/* Control commands run one at a time, in order, on every connection: none
 * while a STEP runs (GCL clients are served meanwhile) or while this
 * client has not read what it was sent. */
static bool may_run(const control_client_t *c)
{
    return !c->closing && !c->dead && !simctl_step_running(&c->ctl->sim.sched) &&
           wsg_outq_used(&c->outq) < CONTROL_OUTQ_LOW;
}

static void run_pending(control_client_t *c)
{
    while (input_left(c) && may_run(c)) {
        if (wsg_gcl_linebuf_feed(&c->input, c->pending[c->pending_at++])) {
            handle_line(c);
        }
    }
}

static void receive(control_client_t *c)
{
    ssize_t n = recv(c->fd, c->pending, sizeof(c->pending), MSG_DONTWAIT);
    if (n > 0) {
        c->pending_len = (size_t)n;
        c->pending_at = 0;
    } else if (n == 0) {
        c->eof = true;
    } else if (errno != EAGAIN && errno != EWOULDBLOCK && errno != EINTR) {
        c->dead = true;
    }
}

static void answer_step_if_done(control_client_t *c)
{
    simctl_t *ctl = c->ctl;
    if (ctl->stepper != c || simctl_step_running(&ctl->sim.sched)) {
        return;
    }
    ctl->stepper = NULL;
    char *reply = simctl_step_reply(ctl);
    if (reply != NULL) {
        record_and_send(c, reply);
        free(reply);
    }
}

/* A STEP ended, inside the scheduler's pass: its reply and the commands
 * queued meanwhile wait for simctl_answer_steps(), outside the pass. */
static void on_step_done(void *ctx)
{
    simctl_t *ctl = ctx;
    ctl->step_ended = true;
}

static bool finished(const control_client_t *c)
{
    bool nothing_left = c->eof && !input_left(c) && c->ctl->stepper != c;
    return c->dead || ((c->closing || nothing_left) && wsg_outq_empty(&c->outq));
}

/* Done with c for now: closed when finished, else watched for what it waits for. */
static void close_or_watch(control_client_t *c)
{
    if (finished(c)) {
        close_client(c);
    } else {
        update_events(c);
    }
}

static void on_client(void *ctx, int fd, short revents)
{
    control_client_t *c = ctx;
    (void)fd;
    if ((revents & POLLOUT) != 0) {
        flush(c);
    }
    answer_step_if_done(c);
    run_pending(c);
    bool readable = (revents & (POLLIN | POLLHUP | POLLERR)) != 0;
    if (readable && !input_left(c) && !c->eof && !c->dead && !c->closing) {
        receive(c);
        run_pending(c);
    }
    close_or_watch(c);
}

/* The stepper gets its reply; every connection runs what it received while
 * the STEP ran, straight away rather than from a writable callback (which
 * would cost two epoll_ctl calls and a pass per STEP). */
bool simctl_answer_steps(simctl_t *ctl)
{
    if (!ctl->step_ended) {
        return false;
    }
    ctl->step_ended = false;
    for (unsigned i = 0; i < CONTROL_CLIENTS_MAX; i++) {
        control_client_t *c = &ctl->clients[i];
        if (!c->in_use) {
            continue;
        }
        answer_step_if_done(c);
        run_pending(c);
        close_or_watch(c);
    }
    return true;
}

static control_client_t *free_slot(simctl_t *ctl)
{
    for (unsigned i = 0; i < CONTROL_CLIENTS_MAX; i++) {
        if (!ctl->clients[i].in_use) {
            return &ctl->clients[i];
        }
    }
    return NULL;
}

static void on_accept(void *ctx, int fd, short revents)
{
    simctl_t *ctl = ctx;
    (void)fd;
    (void)revents;
    struct sockaddr_storage peer;
    socklen_t peer_len = sizeof(peer);
    int client_fd = listener_accept(&ctl->listener, &peer, &peer_len);
    if (client_fd < 0) {
        return;
    }
    control_client_t *c = free_slot(ctl);
    if (c != NULL) {
        wsg_outq_init(&c->outq, malloc(CONTROL_OUTQ_BYTES), CONTROL_OUTQ_BYTES);
    }
    if (c == NULL || c->outq.ring == NULL) {
        host_logf(HAL_LOG_WARN, "control: refused a connection, %d already open",
                  CONTROL_CLIENTS_MAX);
        close(client_fd);
        return;
    }
    c->fd = client_fd;
    c->closing = false;
    c->dead = false;
    c->eof = false;
    c->pending_len = 0;
    c->pending_at = 0;
    c->number = ++ctl->connections;
    c->device = 0;
    wsg_gcl_linebuf_reset(&c->input);
    if (!loop_watch(ctl->listener.loop, client_fd, POLLIN, on_client, c)) {
        free(c->outq.ring);
        close(client_fd);
        return;
    }
    c->in_use = true;
    host_logf(HAL_LOG_INFO, "control ctl%u: connected", c->number);
}

bool simctl_start(simctl_t *ctl, host_loop_t *loop, net_t *net, const char *addr, int port)
{
    ctl->addr = addr != NULL ? addr : DEFAULT_ADDR;
    simctl_step_on_done(&ctl->sim.sched, on_step_done, ctl);
    return listener_start(&ctl->listener, loop, net, "control", ctl->addr, port, on_accept, ctl);
}

int simctl_port(const simctl_t *ctl)
{
    return ctl->listener.fd >= 0 ? net_local_port(ctl->listener.fd) : -1;
}

void simctl_describe(const simctl_t *ctl, char *out, size_t cap)
{
    out[0] = '\0';
    if (ctl->listener.fd >= 0) {
        snprintf(out, cap, ", control %s:%d", ctl->addr, simctl_port(ctl));
    }
}

void simctl_reap(simctl_t *ctl)
{
    listener_resume_when_due(&ctl->listener);
}

void simctl_stop(simctl_t *ctl)
{
    for (unsigned i = 0; i < CONTROL_CLIENTS_MAX; i++) {
        if (ctl->clients[i].in_use) {
            close_client(&ctl->clients[i]);
        }
    }
    listener_stop(&ctl->listener);
}

void simctl_set_diagnostics(simctl_t *ctl, record_t *record, coverage_t *coverage)
{
    ctl->sim.record = record;
    ctl->sim.coverage = coverage;
}
