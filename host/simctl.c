#include "simctl.h"

#include <errno.h>
#include <poll.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <unistd.h>

#include "gcl_linebuf.h"
#include "log.h"
#include "loop.h"
#include "net.h"
#include "outq.h"
#include "record.h"
#include "simctl_cmd.h"

#define CONTROL_CLIENTS_MAX 8
#define CONTROL_OUTQ_BYTES (256u * 1024u)
#define READ_CHUNK 4096
#define DEFAULT_ADDR "127.0.0.1"

typedef struct {
    bool in_use;
    bool closing; /* BYE answered: close once flushed */
    bool dead;    /* the peer went away or failed: close now */
    int fd;
    unsigned number; /* ctl<number> in logs and records */
    gcl_linebuf_t input;
    outq_t outq;
} control_client_t;

static struct {
    int listen_fd;
    const char *addr;
    unsigned connections;
    control_client_t clients[CONTROL_CLIENTS_MAX];
} ctl = {.listen_fd = -1};

static void channel_name(const control_client_t *c, char *out, size_t cap)
{
    snprintf(out, cap, "ctl%u", c->number);
}

static void close_client(control_client_t *c)
{
    loop_unwatch(c->fd);
    close(c->fd);
    outq_free(&c->outq);
    c->in_use = false;
    host_logf(HAL_LOG_INFO, "control ctl%u: closed", c->number);
}

static void flush(control_client_t *c)
{
    static char line[CONTROL_OUTQ_BYTES];
    while (!outq_empty(&c->outq)) {
        size_t len = outq_peek(&c->outq, line, sizeof(line));
        ssize_t sent = send(c->fd, line, len, MSG_NOSIGNAL | MSG_DONTWAIT);
        if (sent < 0 && (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR)) {
            break;
        }
        if (sent < 0) {
            c->dead = true;
            break;
        }
        if ((size_t)sent < len) {
            outq_trim_front(&c->outq, (size_t)sent);
            break;
        }
        outq_pop(&c->outq);
    }
    loop_set_events(c->fd, (short)(POLLIN | (outq_empty(&c->outq) ? 0 : POLLOUT)));
}

static void send_reply(control_client_t *c, const char *reply)
{
    size_t len = strlen(reply);
    char *line = malloc(len + 1);
    if (line == NULL) {
        return;
    }
    memcpy(line, reply, len);
    line[len] = '\n';
    if (len + 1 > 0xffffu || !outq_push(&c->outq, line, len + 1)) {
        host_logf(HAL_LOG_WARN, "control ctl%u: reply too long or not read; closing", c->number);
        c->dead = true;
    }
    free(line);
    flush(c);
}

static void handle_line(control_client_t *c)
{
    const gcl_linebuf_t *lb = &c->input;
    char channel[16];
    channel_name(c, channel, sizeof(channel));
    if (gcl_linebuf_status(lb) == GCL_LINE_OK && strspn(lb->text, " \t") == lb->len) {
        return; /* blank line */
    }
    record_control(channel, '<', lb->text, lb->len);
    char *reply = NULL;
    bool close_after = false;
    if (gcl_linebuf_status(lb) != GCL_LINE_OK) {
        reply = strdup("ERR ? 15 line too long or with control bytes");
    } else {
        reply = simctl_exec(lb->text, lb->len, &close_after);
    }
    if (reply == NULL) {
        return;
    }
    record_control(channel, '>', reply, strlen(reply));
    send_reply(c, reply);
    free(reply);
    c->closing = c->closing || close_after;
}

static void on_client(void *ctx, int fd, short revents)
{
    control_client_t *c = ctx;
    (void)fd;
    if ((revents & POLLOUT) != 0) {
        flush(c);
    }
    uint8_t buf[READ_CHUNK];
    ssize_t n = 0;
    if ((revents & (POLLIN | POLLHUP | POLLERR)) != 0 && !c->dead) {
        n = recv(c->fd, buf, sizeof(buf), MSG_DONTWAIT);
        c->dead = n == 0 || (n < 0 && errno != EAGAIN && errno != EINTR);
    }
    for (ssize_t i = 0; i < n && !c->closing && !c->dead; i++) {
        if (gcl_linebuf_feed(&c->input, buf[i])) {
            handle_line(c);
        }
    }
    if (c->dead || (c->closing && outq_empty(&c->outq))) {
        close_client(c);
    }
}

static control_client_t *free_slot(void)
{
    for (unsigned i = 0; i < CONTROL_CLIENTS_MAX; i++) {
        if (!ctl.clients[i].in_use) {
            return &ctl.clients[i];
        }
    }
    return NULL;
}

static void on_accept(void *ctx, int fd, short revents)
{
    (void)ctx;
    (void)revents;
    int client_fd = accept4(fd, NULL, NULL, SOCK_NONBLOCK | SOCK_CLOEXEC);
    if (client_fd < 0) {
        return;
    }
    control_client_t *c = free_slot();
    if (c == NULL || !outq_init(&c->outq, CONTROL_OUTQ_BYTES)) {
        host_logf(HAL_LOG_WARN, "control: refused a connection, %d already open",
                  CONTROL_CLIENTS_MAX);
        close(client_fd);
        return;
    }
    c->fd = client_fd;
    c->closing = false;
    c->dead = false;
    c->number = ++ctl.connections;
    gcl_linebuf_reset(&c->input);
    if (!loop_watch(client_fd, POLLIN, on_client, c)) {
        outq_free(&c->outq);
        close(client_fd);
        return;
    }
    c->in_use = true;
    host_logf(HAL_LOG_INFO, "control ctl%u: connected", c->number);
}

bool simctl_start(const char *addr, int port)
{
    ctl.addr = addr != NULL ? addr : DEFAULT_ADDR;
    ctl.listen_fd = net_listen(SOCK_STREAM, ctl.addr, port);
    if (ctl.listen_fd < 0 || !loop_watch(ctl.listen_fd, POLLIN, on_accept, NULL)) {
        return false;
    }
    return true;
}

int simctl_port(void)
{
    return ctl.listen_fd >= 0 ? net_local_port(ctl.listen_fd) : -1;
}

const char *simctl_address(void)
{
    return ctl.addr;
}

const char *simctl_describe(void)
{
    static char text[96];
    if (ctl.listen_fd < 0) {
        return "";
    }
    snprintf(text, sizeof(text), ", control %s:%d", ctl.addr, simctl_port());
    return text;
}

void simctl_stop(void)
{
    for (unsigned i = 0; i < CONTROL_CLIENTS_MAX; i++) {
        if (ctl.clients[i].in_use) {
            close_client(&ctl.clients[i]);
        }
    }
    if (ctl.listen_fd >= 0) {
        loop_unwatch(ctl.listen_fd);
        close(ctl.listen_fd);
        ctl.listen_fd = -1;
    }
}
