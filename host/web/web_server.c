/* SPDX-License-Identifier: BSD-3-Clause */
#include "web/web_server.h"

#include <arpa/inet.h>
#include <errno.h>
#include <netinet/in.h>
#include <poll.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/socket.h>
#include <unistd.h>

#include "log.h"
#include "loop.h"
#include "net.h"
#include "web/web_events.h"
#include "http_host.h"
#include "web/web_intake.h"
#include "web/web_internal.h"
#include "web/web_lines.h"
#include "web/web_peer.h"
#include "web/web_routes.h"

/* A client that neither sends nor takes a byte for this long (wall clock)
 * is closed: a stalled upload, an idle keep-alive connection or an event
 * stream nobody reads costs nothing after. */
#define CONNECTION_TIMEOUT_S 30u
/* Each client's socket send buffer (accepted sockets inherit it from the
 * listener): what a stalled page can hold of the event stream. */
#define CLIENT_SNDBUF_BYTES (32 * 1024)
#define CONNECTIONS_MAX WEB_INTAKE_CONNECTIONS_MAX
/* Each connection's memory pool (libmicrohttpd's default is 32 KiB), which
 * it clears for every request on a kept-alive connection: 16 KiB holds a
 * browser's request headers and a WEB_BODY_MAX body with room to spare,
 * and halves what an event stream or a request costs. */
#define CONNECTION_MEMORY 16384u
#define NS_PER_MS 1000000ull
#define NS_PER_S 1000000000ull

/* One request's upload, collected until the last call of the handler. */
typedef struct {
    size_t len;
    bool too_big;
    bool foreign_host; /* its Host header names no name of this server */
    bool url_nul;      /* its URL or query held %00 */
    char body[WEB_BODY_MAX + 1u];
} web_call_t;

struct web_server {
    host_loop_t *loop; /* the daemon's epoll descriptor is watched here */
    struct MHD_Daemon *daemon;
    int listen_fd;
    int epoll_fd;
    int port;
    bool sim_open; /* --sim-bind names a non-loopback address */
    simctl_t *sim; /* the simulation routes' control side */
    /* --http-allow-host: the names served besides addresses and localhost */
    const char *allow_hosts[HOST_HTTP_ALLOW_LISTS_MAX];
    size_t allow_host_count;
    uint64_t mhd_due_ns;    /* MHD's next timeout (monotonic), 0: none */
    bool connection_closed; /* in this MHD_run() */
    char describe[128];
    web_intake_t *intake; /* the connections whose request is arriving */
    web_app_t app;        /* what the routes keep */
};

web_server_t *web_server_create(void)
{
    web_server_t *web = calloc(1, sizeof(*web));
    if (web == NULL) {
        return NULL;
    }
    web->intake = web_intake_create();
    if (web->intake == NULL) {
        free(web);
        return NULL;
    }
    web->listen_fd = -1;
    web->epoll_fd = -1;
    web->port = -1;
    web_app_init(&web->app, NULL); /* the fleet comes with the start */
    return web;
}

void web_server_destroy(web_server_t *web)
{
    if (web != NULL) {
        web_server_stop(web);
        web_intake_destroy(web->intake);
        free(web);
    }
}

static uint64_t earliest_nonzero(uint64_t a, uint64_t b)
{
    if (a == 0) {
        return b;
    }
    return b == 0 || a < b ? a : b;
}

/* Asks MHD when it must run next and the streams when they tick, and wakes
 * the loop then. */
static void schedule(web_server_t *web)
{
    MHD_UNSIGNED_LONG_LONG ms = 0;
    uint64_t now = loop_monotonic_ns();
    web->mhd_due_ns = MHD_get_timeout(web->daemon, &ms) == MHD_YES ? now + ms * NS_PER_MS : 0;
    uint64_t wake = earliest_nonzero(web->mhd_due_ns, web_events_next_tick_ns(&web->app.events));
    wake = earliest_nonzero(wake, web_intake_next_due_ns(web->intake));
    if (web_events_resuming(&web->app.events)) {
        loop_wake_at_wall(web->loop, LOOP_NOW); /* the next streams after one look around */
    } else if (wake != 0) {
        loop_wake_at_wall(web->loop, wake);
    }
}

static void run_mhd(web_server_t *web)
{
    do {
        /* MHD takes its listening socket back into its epoll set only in the
         * run after a connection closed at its limit: run again, or a client
         * waiting in the backlog would wait for the next one to connect */
        web->connection_closed = false;
        MHD_run(web->daemon);
    } while (web->connection_closed);
    schedule(web);
}

static void on_epoll_ready(void *ctx, int fd, short revents)
{
    (void)fd;
    (void)revents;
    run_mhd(ctx);
}

void web_server_poll(web_server_t *web)
{
    uint64_t intake_due_ns = web_intake_next_due_ns(web->intake);
    if (web->daemon == NULL ||
        (web->mhd_due_ns == 0 && web_events_next_tick_ns(&web->app.events) == 0 &&
         !web_events_resuming(&web->app.events) && intake_due_ns == 0)) {
        return;
    }
    uint64_t now = loop_monotonic_ns();
    bool ticked = web_events_tick(&web->app.events, now); /* resumes the streams that are due */
    if (intake_due_ns != 0 && now >= intake_due_ns) {
        /* what has arrived is read first: a server held up (a loaded host,
         * valgrind) cuts no request that came in time */
        run_mhd(web);
        unsigned cut = web_intake_cut_late(web->intake, now);
        if (cut > 0) {
            host_logf(HAL_LOG_DEBUG, "http: cut %u connection(s) whose request was late", cut);
            run_mhd(web);
        }
    } else if (ticked || (web->mhd_due_ns != 0 && now >= web->mhd_due_ns)) {
        run_mhd(web);
    } else {
        schedule(web);
    }
}

/* The intake record of a connection (web_intake.h), NULL when it has none. */
static web_intake_conn_t *intake_of(struct MHD_Connection *connection)
{
    const union MHD_ConnectionInfo *info =
        MHD_get_connection_info(connection, MHD_CONNECTION_INFO_SOCKET_CONTEXT);
    return info != NULL ? info->socket_context : NULL;
}

/* Accepting a connection: refused when its client already has
 * WEB_INTAKE_PER_ADDRESS connections whose request is arriving. */
static enum MHD_Result admit_client(void *cls, const struct sockaddr *addr, socklen_t addrlen)
{
    const web_server_t *web = cls;
    (void)addrlen;
    if (web_intake_admits(web->intake, addr)) {
        return MHD_YES;
    }
    host_logf(HAL_LOG_DEBUG, "http: refused a connection: its client has %u requests arriving",
              WEB_INTAKE_PER_ADDRESS);
    return MHD_NO;
}

static void connection_changed(void *cls, struct MHD_Connection *connection, void **socket_context,
                               enum MHD_ConnectionNotificationCode code)
{
    web_server_t *web = cls;
    if (code != MHD_CONNECTION_NOTIFY_STARTED) {
        web_intake_close(web->intake, *socket_context);
        *socket_context = NULL;
        web->connection_closed = true;
        return;
    }
    const union MHD_ConnectionInfo *fd =
        MHD_get_connection_info(connection, MHD_CONNECTION_INFO_CONNECTION_FD);
    const union MHD_ConnectionInfo *addr =
        MHD_get_connection_info(connection, MHD_CONNECTION_INFO_CLIENT_ADDRESS);
    if (fd == NULL) {
        return;
    }
    *socket_context = web_intake_open(web->intake, fd->connect_fd,
                                      addr != NULL ? addr->client_addr : NULL, loop_monotonic_ns());
    if (*socket_context == NULL) {
        shutdown(fd->connect_fd, SHUT_RDWR); /* no record: MHD closes it at once */
    }
}

static void request_completed(void *cls, struct MHD_Connection *connection, void **req_cls,
                              enum MHD_RequestTerminationCode toe)
{
    web_server_t *web = cls;
    (void)toe;
    free(*req_cls);
    *req_cls = NULL;
    web_intake_waiting(web->intake, intake_of(connection), loop_monotonic_ns()); /* keep-alive */
}

/* The Host header names this server (http_host.h). A request without one is
 * not a browser's (browsers always send it), and browsers are the one kind
 * of client a rebound name can fool: it is served. */
static bool host_allowed(const web_server_t *web, struct MHD_Connection *connection)
{
    const char *host =
        MHD_lookup_connection_value(connection, MHD_HEADER_KIND, MHD_HTTP_HEADER_HOST);
    return host == NULL || http_host_allowed(host, web->allow_hosts, web->allow_host_count);
}

/* The first call of a request: its upload buffer; a foreign Host (403) or a
 * declared length that is already too large (413) is answered at once,
 * before the body is read, and MHD then closes the connection instead of
 * reading what a client claims. */
static enum MHD_Result begin_request(const web_server_t *web, struct MHD_Connection *connection,
                                     void **req_cls)
{
    web_call_t *call = calloc(1, sizeof(*call));
    if (call == NULL) {
        return MHD_NO;
    }
    *req_cls = call;
    call->foreign_host = !host_allowed(web, connection);
    call->url_nul = web_intake_take_nul(intake_of(connection));
    const char *length =
        MHD_lookup_connection_value(connection, MHD_HEADER_KIND, MHD_HTTP_HEADER_CONTENT_LENGTH);
    call->too_big = length != NULL && strtoull(length, NULL, 10) > WEB_BODY_MAX;
    return MHD_YES;
}

/* Keeps at most WEB_BODY_MAX bytes of a body without a declared length
 * (chunked); the rest is read and dropped, and the request answered with 413. */
static void collect_upload(web_call_t *call, const char *data, size_t len)
{
    if (call->too_big || len > WEB_BODY_MAX - call->len) {
        call->too_big = true;
        return;
    }
    memcpy(call->body + call->len, data, len);
    call->len += len;
    call->body[call->len] = '\0';
}

/* A request that may change the device (every route but GET). */
static bool changes_state(const char *method)
{
    return strcmp(method, MHD_HTTP_METHOD_GET) != 0 && strcmp(method, MHD_HTTP_METHOD_HEAD) != 0;
}

/* The host part of an Origin header ("http://host:port" -> "host:port"). */
static const char *origin_host(const char *origin)
{
    const char *scheme_end = strstr(origin, "://");
    return scheme_end != NULL ? scheme_end + 3 : origin;
}

/* A page of another site may not drive the gripper through the visitor's
 * browser: a changing request must say it carries JSON (a cross-site page
 * cannot send that without a preflight, which is never granted), and an
 * Origin, when the browser sends one, must be this server (DNS rebinding,
 * forms). True with the refusal queued. */
static bool refuse_cross_site(const web_request_t *req, enum MHD_Result *refused)
{
    const char *type =
        MHD_lookup_connection_value(req->connection, MHD_HEADER_KIND, MHD_HTTP_HEADER_CONTENT_TYPE);
    if (type == NULL || strncasecmp(type, "application/json", 16) != 0) {
        *refused = web_reply_error(req, MHD_HTTP_UNSUPPORTED_MEDIA_TYPE, E_CMD_FORMAT_ERROR,
                                   "a request that changes the device must have Content-Type: "
                                   "application/json");
        return true;
    }
    const char *origin =
        MHD_lookup_connection_value(req->connection, MHD_HEADER_KIND, MHD_HTTP_HEADER_ORIGIN);
    const char *host =
        MHD_lookup_connection_value(req->connection, MHD_HEADER_KIND, MHD_HTTP_HEADER_HOST);
    if (origin != NULL && (host == NULL || strcmp(origin_host(origin), host) != 0)) {
        *refused = web_reply_error(req, MHD_HTTP_FORBIDDEN, E_ACCESS_DENIED,
                                   "a request from the page of another site (Origin %s)", origin);
        return true;
    }
    return false;
}

static enum MHD_Result handle(void *cls, struct MHD_Connection *connection, const char *url,
                              const char *method, const char *version, const char *upload_data,
                              size_t *upload_data_size, void **req_cls)
{
    web_server_t *web = cls;
    (void)version;
    bool first_call = *req_cls == NULL;
    if (first_call && begin_request(web, connection, req_cls) == MHD_NO) {
        return MHD_NO;
    }
    web_call_t *call = *req_cls;
    if (first_call && !call->too_big && !call->foreign_host && !call->url_nul) {
        return MHD_YES;
    }
    if (*upload_data_size > 0) {
        collect_upload(call, upload_data, *upload_data_size);
        *upload_data_size = 0;
        return MHD_YES;
    }
    web_intake_arrived(web->intake, intake_of(connection));
    const union MHD_ConnectionInfo *info =
        MHD_get_connection_info(connection, MHD_CONNECTION_INFO_CLIENT_ADDRESS);
    web_request_t req = {
        .app = &web->app,
        .connection = connection,
        .method = method,
        .url = url,
        .body = call->body,
        .body_len = call->len,
        .sim_allowed = web->sim_open || (info != NULL && web_peer_is_loopback(info->client_addr)),
        .sim = web->sim,
    };
    if (call->foreign_host) {
        return web_reply_error(
            &req, MHD_HTTP_FORBIDDEN, E_ACCESS_DENIED,
            "this server does not answer to the name in the Host header (%.64s): use its IP "
            "address or localhost, or start wsgsim with --http-allow-host NAME",
            MHD_lookup_connection_value(connection, MHD_HEADER_KIND, MHD_HTTP_HEADER_HOST));
    }
    if (call->url_nul) {
        return web_reply_error(&req, MHD_HTTP_BAD_REQUEST, E_INVALID_PARAMETER,
                               "the URL holds a NUL character (%%00)");
    }
    if (call->too_big) {
        return web_reply_error(&req, MHD_HTTP_CONTENT_TOO_LARGE, E_OVERRUN,
                               "the request body is larger than %u bytes", WEB_BODY_MAX);
    }
    if (changes_state(method)) {
        enum MHD_Result refused;
        if (refuse_cross_site(&req, &refused)) {
            return refused;
        }
    }
    return web_routes_dispatch(&req);
}

/* MHD's own decoding of %HH escapes in the path and the query, noting a
 * %00: the URL a route sees is a C string and would end there
 * ("files/x%00.lua" would name "x"), so such a request is refused whole. */
static size_t unescape(void *cls, struct MHD_Connection *connection, char *text)
{
    (void)cls;
    size_t len = MHD_http_unescape(text);
    if (strlen(text) != len) {
        web_intake_note_nul(intake_of(connection));
    }
    return len;
}

static void log_mhd(void *cls, const char *fmt, va_list ap)
{
    (void)cls;
    char text[256];
    vsnprintf(text, sizeof(text), fmt, ap);
    text[strcspn(text, "\n")] = '\0';
    host_logf(HAL_LOG_DEBUG, "http: %s", text);
}

static bool open_daemon(web_server_t *web)
{
    /* the logger first: MHD logs (and complains) while reading the options */
    web->daemon = MHD_start_daemon(
        MHD_USE_EPOLL | MHD_ALLOW_SUSPEND_RESUME | MHD_USE_ERROR_LOG, 0, admit_client, web, handle,
        web, MHD_OPTION_EXTERNAL_LOGGER, log_mhd, NULL, MHD_OPTION_LISTEN_SOCKET, web->listen_fd,
        MHD_OPTION_CONNECTION_TIMEOUT, (unsigned)CONNECTION_TIMEOUT_S, MHD_OPTION_CONNECTION_LIMIT,
        (unsigned)CONNECTIONS_MAX, MHD_OPTION_CONNECTION_MEMORY_LIMIT, (size_t)CONNECTION_MEMORY,
        MHD_OPTION_NOTIFY_COMPLETED, request_completed, web, MHD_OPTION_NOTIFY_CONNECTION,
        connection_changed, web, MHD_OPTION_UNESCAPE_CALLBACK, unescape, NULL, MHD_OPTION_END);
    if (web->daemon == NULL) {
        return false;
    }
    const union MHD_DaemonInfo *info = MHD_get_daemon_info(web->daemon, MHD_DAEMON_INFO_EPOLL_FD);
    web->epoll_fd = info != NULL ? info->epoll_fd : -1;
    return web->epoll_fd >= 0 && loop_watch(web->loop, web->epoll_fd, POLLIN, on_epoll_ready, web);
}

static bool sim_bind_open(const char *sim_bind)
{
    unsigned char addr[sizeof(struct in6_addr)];
    if (sim_bind == NULL) {
        return false;
    }
    if (inet_pton(AF_INET, sim_bind, addr) == 1) {
        return addr[0] != 127u;
    }
    return inet_pton(AF_INET6, sim_bind, addr) == 1 &&
           !IN6_IS_ADDR_LOOPBACK((const struct in6_addr *)addr);
}

/* The ready line's URL names an address a browser on this host can open:
 * the loopback address for a wildcard bind, else the bound one. */
static const char *url_host(const char *bind)
{
    if (strcmp(bind, "0.0.0.0") == 0) {
        return "127.0.0.1";
    }
    return strcmp(bind, "::") == 0 ? "::1" : bind;
}

bool web_server_start(web_server_t *web, host_loop_t *loop, net_t *net, const host_options_t *opts,
                      simctl_t *sim, struct fleet *fleet)
{
    web->loop = loop;
    web->sim = sim;
    web->app.fleet = fleet;
    web->app.sim = sim;
    if (opts->http_port == 0) {
        return true;
    }
    const char *bind = opts->http_bind != NULL ? opts->http_bind : opts->bind_addr;
    /* the default port is skipped when taken: a warning, not an error line */
    bool asked = opts->http_port_given || opts->http_bind != NULL;
    web->listen_fd = asked ? net_listen(net, SOCK_STREAM, bind, opts->http_port)
                           : net_listen_optional(net, SOCK_STREAM, bind, opts->http_port);
    if (web->listen_fd < 0) {
        if (!asked) {
            host_logf(HAL_LOG_WARN, "http port %d cannot be had (%s): no web interface",
                      opts->http_port, strerror(errno));
        }
        return !asked;
    }
    int sndbuf = CLIENT_SNDBUF_BYTES;
    setsockopt(web->listen_fd, SOL_SOCKET, SO_SNDBUF, &sndbuf, sizeof(sndbuf));
    web->sim_open = sim_bind_open(opts->sim_bind);
    web->allow_host_count = (size_t)opts->http_allow_host_count;
    memcpy(web->allow_hosts, opts->http_allow_hosts, sizeof(web->allow_hosts));
    web_intake_reset(web->intake, (uint64_t)opts->http_request_timeout_s * NS_PER_S);
    if (!open_daemon(web)) {
        host_logf(HAL_LOG_ERROR, "http: cannot start the web server");
        web_server_stop(web);
        return false;
    }
    web->port = net_local_port(web->listen_fd);
    web_lines_enable(&web->app.lines, (unsigned)opts->devices);
    char endpoint[96];
    net_format_endpoint(url_host(bind), web->port, endpoint, sizeof(endpoint));
    snprintf(web->describe, sizeof(web->describe), ", web page http://%s/", endpoint);
    return true;
}

const char *web_server_describe(const web_server_t *web)
{
    return web->daemon != NULL ? web->describe : "";
}

int web_server_port(const web_server_t *web)
{
    return web->daemon != NULL ? web->port : -1;
}

void web_server_stop(web_server_t *web)
{
    if (web->daemon != NULL) {
        web_events_end_all(&web->app.events); /* MHD stops only with no connection suspended */
        MHD_run(web->daemon);
        loop_unwatch(web->loop, web->epoll_fd);
        MHD_stop_daemon(web->daemon); /* closes the listening socket too */
        web->daemon = NULL;
        web->listen_fd = -1;
    }
    if (web->listen_fd >= 0) {
        close(web->listen_fd);
        web->listen_fd = -1;
    }
    web_app_release(&web->app);
    web->epoll_fd = -1;
    web->port = -1;
    web->mhd_due_ns = 0;
}

web_lines_t *web_server_lines(web_server_t *web)
{
    return web->daemon != NULL ? &web->app.lines : NULL;
}
