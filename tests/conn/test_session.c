/* SPDX-License-Identifier: BSD-3-Clause */
/* Sessions: per-session settings, BYE and disconnects, several clients,
 * datagram peers, slot reuse and the observer hooks. */
#include <check.h>
#include <string.h>

#include "fake_device.h"
#include "unit_suites.h"
#include "wsg/wsg_bin.h"

/* --- per-session settings --- */

START_TEST(pwt_clt_are_per_session)
{
    h_open(&h_other, WSG_TRANSPORT_STREAM);
    ASK_EQ("PWT=5", "PWT=5.0");
    ASK_EQ("CLT=3", "CLT=3.0");
    ck_assert_str_eq(ask(&h_other, "PWT?"), "PWT=10.0");
    ck_assert_str_eq(ask(&h_other, "CLT?"), "CLT=10.0");
    ASK_EQ("PWT?", "PWT=5.0");
    ASK_EQ("CLT?", "CLT=3.0");
}
END_TEST

START_TEST(settings_reset_on_new_session)
{
    ASK_EQ("PWT=5", "PWT=5.0");
    ASK_EQ("CLT=3", "CLT=3.0");
    ASK_EQ("VERBOSE=1", "VERBOSE=1");
    uint64_t id = wsg_conn_id(&h_main.conn);
    ASK_EQ("BYE()", "ACK BYE");
    h_close(&h_main, WSG_CLOSE_ANNOUNCED);
    h_open(&h_main, WSG_TRANSPORT_STREAM); /* the same storage, fresh settings */
    ck_assert_uint_gt(wsg_conn_id(&h_main.conn), id);
    ASK_EQ("PWT?", "PWT=10.0");
    ASK_EQ("CLT?", "CLT=10.0");
    ASK_EQ("VERBOSE?", "VERBOSE=0");
    ASK_EQ("FOO()", "ERR FOO 14");
}
END_TEST

START_TEST(verbose_is_per_session)
{
    h_open(&h_other, WSG_TRANSPORT_STREAM);
    ASK_EQ("VERBOSE=1", "VERBOSE=1");
    ck_assert_str_eq(ask(&h_other, "FOO()"), "ERR FOO 14");
    ASK_EQ("FOO()", "ERR FOO 14 Unknown command");
}
END_TEST

/* --- BYE and disconnects --- */

START_TEST(bye)
{
    ck_assert(!wsg_conn_wants_close(&h_main.conn));
    ck_assert(!wsg_conn_close_announced(&h_main.conn));
    ASK_EQ("BYE()", "ACK BYE");
    ck_assert(wsg_conn_wants_close(&h_main.conn));
    ck_assert(wsg_conn_close_announced(&h_main.conn));
    SEND("POS?"); /* input after BYE is ignored */
    EXPECT_NONE();
}
END_TEST

START_TEST(bye_ends_the_feed)
{
    const char *text = "BYE()\nPOS?\n";
    h_send_bytes(&h_main, text, strlen(text));
    EXPECT("ACK BYE");
    EXPECT_NONE();
}
END_TEST

START_TEST(close_after_bye_keeps_running)
{
    ASK_EQ("BYE()", "ACK BYE");
    h_close(&h_main, WSG_CLOSE_DROPPED); /* the port may only notice the socket closing */
    ck_assert(!wsg_conn_is_open(&h_main.conn));
    h_open(&h_other, WSG_TRANSPORT_STREAM);
    ck_assert_str_eq(ask(&h_other, "SYSFLAGS[12]?"), "SYSFLAGS[12]=0");
    ck_assert_str_eq(ask(&h_other, "GRIPSTATE?"), "GRIPSTATE=0");
}
END_TEST

START_TEST(drop_without_bye_raises_fast_stop)
{
    h_open(&h_other, WSG_TRANSPORT_STREAM);
    h_close(&h_other, WSG_CLOSE_DROPPED);
    ASK_EQ("SYSFLAGS[12]?", "SYSFLAGS[12]=1");
    ASK_EQ("GRIPSTATE?", "GRIPSTATE=7");
    ck_assert(h_log_contains(HAL_LOG_WARN, "without BYE"));
    ASK_EQ("HOME()", "ERR HOME 16");
    ASK_EQ("FSACK()", "ACK FSACK");
    ASK_EQ("HOME()", "ACK HOME");
}
END_TEST

START_TEST(drop_without_bye_can_be_disabled)
{
    h_cfg()->disconnect_raises_faststop = false;
    h_open(&h_other, WSG_TRANSPORT_STREAM);
    h_close(&h_other, WSG_CLOSE_DROPPED);
    ASK_EQ("SYSFLAGS[12]?", "SYSFLAGS[12]=0");
}
END_TEST

START_TEST(drop_during_move_aborts_it)
{
    ASK_EQ("HOME()", "ACK HOME");
    ck_assert_int_ge(run_until_line(&h_main, "FIN HOME", 3000), 0);
    h_open(&h_other, WSG_TRANSPORT_STREAM);
    ck_assert_str_eq(ask(&h_other, "MOVE(10)"), "ACK MOVE");
    advance_ms(100);
    h_close(&h_other, WSG_CLOSE_DROPPED);
    advance_ms(100);
    EXPECT_NONE(); /* the abort belonged to the dropped session */
    ASK_EQ("SPEED?", "SPEED=0.0");
    ASK_EQ("SYSFLAGS[12]?", "SYSFLAGS[12]=1");
    ASK_EQ("SYSFLAGS[1]?", "SYSFLAGS[1]=0");
    ck_assert_float_gt(ask_float("POS?"), 50.0f);
}
END_TEST

START_TEST(datagram_peers)
{
    h_open(&h_other, WSG_TRANSPORT_DATAGRAM);
    h_send_bytes(&h_other, "POS?", 4);
    expect_no_line(&h_other);
    wsg_conn_end_datagram(&h_other.conn);
    expect_line(&h_other, "POS=55.0");
    wsg_conn_end_datagram(&h_other.conn); /* nothing pending: nothing */
    expect_no_line(&h_other);
    h_close(&h_other, WSG_CLOSE_DROPPED); /* UDP has no connection to lose */
    h_open(&h_third, WSG_TRANSPORT_DATAGRAM);
    h_close(&h_third, WSG_CLOSE_EXPIRED);
    ASK_EQ("SYSFLAGS[12]?", "SYSFLAGS[12]=0");
}
END_TEST

START_TEST(datagram_with_newline)
{
    h_open(&h_other, WSG_TRANSPORT_DATAGRAM);
    h_send_bytes(&h_other, "SN?\nTAG?\n", 9);
    wsg_conn_end_datagram(&h_other.conn);
    expect_line(&h_other, "SN=12345678");
    expect_line(&h_other, "TAG=\"wsgsim\"");
    expect_no_line(&h_other);
}
END_TEST

/* --- several clients --- */

START_TEST(final_line_goes_to_issuer_only)
{
    h_open(&h_other, WSG_TRANSPORT_STREAM);
    ck_assert_str_eq(ask(&h_other, "HOME()"), "ACK HOME");
    EXPECT_NONE();
    ASK_EQ("HOME()", "ERR HOME 4");
    expect_no_line(&h_other);
    ck_assert_int_ge(run_until_line(&h_other, "FIN HOME", 3000), 0);
    EXPECT_NONE();
    ASK_EQ("MOVE(30)", "ACK MOVE");
    ck_assert_int_ge(run_until_line(&h_main, "FIN MOVE", 3000), 0);
    expect_no_line(&h_other);
}
END_TEST

START_TEST(stop_from_another_session)
{
    ASK_EQ("HOME()", "ACK HOME");
    ck_assert_int_ge(run_until_line(&h_main, "FIN HOME", 3000), 0);
    h_open(&h_other, WSG_TRANSPORT_STREAM);
    ASK_EQ("MOVE(10)", "ACK MOVE");
    advance_ms(100);
    ck_assert_str_eq(ask(&h_other, "STOP()"), "ACK STOP");
    EXPECT("ERR MOVE 19"); /* at once, to the session that moved */
    EXPECT_NONE();
    expect_no_line(&h_other);
}
END_TEST

START_TEST(queries_during_another_sessions_motion)
{
    h_open(&h_other, WSG_TRANSPORT_STREAM);
    ck_assert_str_eq(ask(&h_other, "HOME()"), "ACK HOME");
    advance_ms(200);
    ASK_EQ("GRIPSTATE?", "GRIPSTATE=6");
    ASK_EQ("SYSFLAGS[1]?", "SYSFLAGS[1]=1");
    expect_no_line(&h_other);
}
END_TEST

START_TEST(final_line_not_delivered_to_slot_reuser)
{
    ASK_EQ("HOME()", "ACK HOME");
    ASK_EQ("BYE()", "ACK BYE");
    h_close(&h_main, WSG_CLOSE_ANNOUNCED);
    h_open(&h_main, WSG_TRANSPORT_STREAM); /* a new connection in the same storage */
    advance_ms(2000);
    EXPECT_NONE();
    ASK_EQ("SYSFLAGS[0]?", "SYSFLAGS[0]=1"); /* homing did finish */
}
END_TEST

static unsigned sink_lines;

static void sink_write(void *ctx, const char *line, size_t len, wsg_msg_kind_t kind)
{
    (void)ctx;
    (void)line;
    (void)len;
    (void)kind;
    sink_lines++;
}

/* Regression: 16-bit session ids wrapped after 65536 sessions, and a reused
 * slot's new session then took the FIN of a motion its predecessor started.
 * Now the owner is detached on close: no id is compared at all. */
START_TEST(final_line_not_delivered_after_65536_sessions)
{
    static const wsg_conn_io_t sink = {.write = sink_write};
    static wsg_conn_t reused;
    ASK_EQ("HOME()", "ACK HOME");
    h_close(&h_main, WSG_CLOSE_EXPIRED);
    for (unsigned i = 0; i < 65535u; i++) {
        wsg_conn_open(&reused, &h_dev, &wsg_gcl_driver, WSG_TRANSPORT_DATAGRAM, &sink, NULL);
        wsg_conn_close(&reused, WSG_CLOSE_EXPIRED);
    }
    h_open(&h_main, WSG_TRANSPORT_DATAGRAM);
    advance_ms(2000);
    EXPECT_NONE();
    ck_assert_uint_eq(sink_lines, 0);
    ASK_EQ("SYSFLAGS[0]?", "SYSFLAGS[0]=1"); /* homing did finish */
}
END_TEST

/* The port owns connection storage: the device serves as many as it is
 * given, and iterates only the open ones. */
START_TEST(connections_are_the_ports)
{
    static const wsg_conn_io_t sink = {.write = sink_write};
    static wsg_conn_t many[200];
    sink_lines = 0;
    for (unsigned i = 0; i < 200u; i++) {
        wsg_conn_open(&many[i], &h_dev, &wsg_gcl_driver, WSG_TRANSPORT_STREAM, &sink, NULL);
    }
    wsg_conn_input(&many[199], (const uint8_t *)"SN?\n", 4);
    ck_assert_uint_eq(sink_lines, 1);
    unsigned open = 0;
    for (wsg_conn_t *c = wsg_device_conn_first(&h_dev); c != NULL; c = wsg_conn_next(c)) {
        open++;
    }
    ck_assert_uint_eq(open, 201); /* h_main too */
    for (unsigned i = 0; i < 200u; i++) {
        wsg_conn_close(&many[i], WSG_CLOSE_EXPIRED);
    }
    ck_assert_ptr_eq(wsg_device_conn_first(&h_dev), &h_main.conn);
    ck_assert_ptr_null(wsg_conn_next(&h_main.conn));
}
END_TEST

START_TEST(closing_twice_is_harmless)
{
    ASK_EQ("BYE()", "ACK BYE");
    wsg_conn_close(&h_main.conn, WSG_CLOSE_ANNOUNCED);
    wsg_conn_close(&h_main.conn, WSG_CLOSE_DROPPED);
    h_open(&h_other, WSG_TRANSPORT_STREAM);
    ck_assert_str_eq(ask(&h_other, "SYSFLAGS[12]?"), "SYSFLAGS[12]=0");
}
END_TEST

/* --- observer hooks --- */

static struct {
    unsigned lines_in, lines_out, done, tolerated, state_changes;
    char last_done[16];
    unsigned last_form, last_argc;
    wsg_status_t last_status;
    wsg_grip_state_t last_to;
} seen;

static void on_line_in(void *ctx, const wsg_conn_t *c, const char *line, size_t len)
{
    (void)ctx, (void)c, (void)line, (void)len;
    seen.lines_in++;
}

static void on_line_out(void *ctx, const wsg_conn_t *c, const char *line, size_t len)
{
    (void)ctx, (void)c;
    ck_assert(len > 0 && line[len - 1] == '\n');
    seen.lines_out++;
}

static void on_state(void *ctx, wsg_grip_state_t from, wsg_grip_state_t to)
{
    (void)ctx;
    ck_assert_int_ne(from, to);
    seen.state_changes++;
    seen.last_to = to;
}

static void on_done(void *ctx, const wsg_conn_t *c, const char *name, int index, unsigned form,
                    unsigned argc, wsg_status_t status)
{
    (void)ctx, (void)c;
    ck_assert_int_eq(index, wsg_gcl_command_index(name));
    seen.done++;
    strncpy(seen.last_done, name, sizeof(seen.last_done) - 1);
    seen.last_form = form;
    seen.last_argc = argc;
    seen.last_status = status;
}

static void on_tolerated(void *ctx, const wsg_conn_t *c, const char *name, const char *what)
{
    (void)ctx, (void)c, (void)name, (void)what;
    seen.tolerated++;
}

static wsg_conn_observer_t conn_hooks = {.message_in = on_line_in, .message_out = on_line_out};
static wsg_device_observer_t device_hooks = {.grip_state_changed = on_state};
static wsg_gcl_observer_t gcl_hooks = {.command_done = on_done, .tolerated = on_tolerated};

static void attach_all(void)
{
    memset(&seen, 0, sizeof(seen));
    wsg_conn_add_observer(&h_dev, &conn_hooks);
    wsg_device_add_observer(&h_dev, &device_hooks);
    wsg_gcl_add_observer(&h_dev, &gcl_hooks);
}

START_TEST(hooks_observe_the_device)
{
    attach_all();
    ASK_EQ("MOVE(1,2,3)", "ERR MOVE 12");
    ck_assert_str_eq(seen.last_done, "MOVE");
    ck_assert_uint_eq(seen.last_form, WSG_GCL_FORM_CALL);
    ck_assert_uint_eq(seen.last_argc, 3);
    ck_assert_int_eq(seen.last_status, E_NO_PARAM_EXPECTED);
    ASK_EQ("AUTOSEND(POS,0)", "ACK AUTOSEND"); /* unquoted string: tolerated */
    ck_assert_uint_eq(seen.tolerated, 1);
    ASK_EQ("HOME()", "ACK HOME");
    ck_assert_uint_eq(seen.state_changes, 1);
    ck_assert_int_eq(seen.last_to, GS_POSITIONING);
    ck_assert_uint_eq(seen.lines_in, 3);
    ck_assert_uint_eq(seen.lines_out, 3);
    ck_assert_uint_eq(seen.done, 3);
    ck_assert_uint_eq(h_gcl_lines_in(&h_main), 3);
    ck_assert_uint_eq(h_gcl_lines_out(&h_main), 3);
}
END_TEST

/* Observers survive a reset (power-on keeps them, as the control channel's
 * RESET expects its own re-attachment to be the only change). */
START_TEST(hooks_survive_reset)
{
    attach_all();
    h_close(&h_main, WSG_CLOSE_EXPIRED);
    wsg_device_reset(&h_dev, h_cfg());
    ck_assert_ptr_null(wsg_device_conn_first(&h_dev)); /* power-on: no connections */
    h_open(&h_main, WSG_TRANSPORT_STREAM);
    ASK_EQ("SN?", "SN=12345678");
    ck_assert_uint_eq(seen.lines_out, 1);
}
END_TEST

/* Observers are lists: each node says who it is through its ctx,
 * and every call is logged as "<who><what>" in the order it happened. */
static char calls[64];

static void log_call(void *ctx, char what)
{
    size_t n = strlen(calls);
    if (n + 2 < sizeof(calls)) {
        calls[n] = *(const char *)ctx;
        calls[n + 1] = what;
        calls[n + 2] = '\0';
    }
}

static void log_in(void *ctx, const wsg_conn_t *c, const char *line, size_t len)
{
    (void)c, (void)line, (void)len;
    log_call(ctx, '<');
}

static void log_out(void *ctx, const wsg_conn_t *c, const char *line, size_t len)
{
    (void)c, (void)line, (void)len;
    log_call(ctx, '>');
}

static void log_state(void *ctx, wsg_grip_state_t from, wsg_grip_state_t to)
{
    (void)from, (void)to;
    log_call(ctx, 's');
}

static void log_done(void *ctx, const wsg_conn_t *c, const char *name, int index, unsigned form,
                     unsigned argc, wsg_status_t status)
{
    (void)c, (void)name, (void)index, (void)form, (void)argc, (void)status;
    log_call(ctx, 'd');
}

static void log_error(void *ctx, const wsg_conn_t *c, int index, wsg_status_t status)
{
    (void)c, (void)index, (void)status;
    log_call(ctx, 'e');
}

static void log_tolerated(void *ctx, const wsg_conn_t *c, const char *name, const char *what)
{
    (void)c, (void)name, (void)what;
    log_call(ctx, 't');
}

static char name_a = 'A', name_b = 'B';
static wsg_conn_observer_t conn_a = {.message_in = log_in, .message_out = log_out, .ctx = &name_a};
static wsg_conn_observer_t conn_b = {.message_in = log_in, .message_out = log_out, .ctx = &name_b};

START_TEST(two_message_observers_hear_every_message_in_the_order_added)
{
    calls[0] = '\0';
    wsg_conn_add_observer(&h_dev, &conn_a);
    wsg_conn_add_observer(&h_dev, &conn_b);
    wsg_conn_add_observer(&h_dev, &conn_a); /* already on the list: nothing */
    ASK_EQ("SN?", "SN=12345678");
    ck_assert_str_eq(calls, "A<B<A>B>");
}
END_TEST

START_TEST(a_removed_message_observer_hears_nothing_more)
{
    calls[0] = '\0';
    wsg_conn_add_observer(&h_dev, &conn_a);
    wsg_conn_add_observer(&h_dev, &conn_b);
    wsg_conn_remove_observer(&h_dev, &conn_a); /* the head */
    ASK_EQ("SN?", "SN=12345678");
    ck_assert_str_eq(calls, "B<B>");
    wsg_conn_remove_observer(&h_dev, &conn_a); /* not on the list: nothing */
    wsg_conn_add_observer(&h_dev, &conn_a);    /* back, now after B */
    wsg_conn_remove_observer(&h_dev, &conn_b);
    calls[0] = '\0';
    ASK_EQ("SN?", "SN=12345678");
    ck_assert_str_eq(calls, "A<A>");
    wsg_conn_remove_observer(&h_dev, &conn_a);
    calls[0] = '\0';
    ASK_EQ("SN?", "SN=12345678");
    ck_assert_str_eq(calls, "");
}
END_TEST

static size_t read_len;
static bool closed_fast_stop;
static wsg_close_reason_t closed_why;

static void log_read(void *ctx, const wsg_conn_t *c, const uint8_t *bytes, size_t len)
{
    (void)c, (void)bytes;
    read_len = len;
    log_call(ctx, 'r');
}

static void log_closed(void *ctx, const wsg_conn_t *c, wsg_close_reason_t why, bool fast_stop)
{
    ck_assert(wsg_conn_partial_input(c)); /* still readable: before the driver lets go */
    closed_why = why;
    closed_fast_stop = fast_stop;
    log_call(ctx, 'c');
}

static wsg_conn_observer_t conn_reader = {.message_in = log_in,
                                          .message_out = log_out,
                                          .ctx = &name_a,
                                          .read = log_read,
                                          .closed = log_closed};

/* A read is shown before the messages it carries, once, however many it
 * carries; the close before the connection is detached, with its reason
 * and whether it raised FAST STOP. An observer without read() is not
 * called for reads. */
START_TEST(a_read_comes_before_its_messages_and_a_close_is_shown)
{
    calls[0] = '\0';
    wsg_conn_add_observer(&h_dev, &conn_b); /* no read() */
    wsg_conn_add_observer(&h_dev, &conn_reader);
    h_send_bytes(&h_main, "SN?\nSN?\n", 8);
    ck_assert_str_eq(calls, "ArB<A<B>A>B<A<B>A>");
    ck_assert_uint_eq(read_len, 8);
    calls[0] = '\0';
    h_send_bytes(&h_main, "SN", 2); /* half a line: a read, no message */
    ck_assert_str_eq(calls, "Ar");
    h_close(&h_main, WSG_CLOSE_DROPPED);
    ck_assert_str_eq(calls, "ArAc");
    ck_assert_int_eq(closed_why, WSG_CLOSE_DROPPED);
    ck_assert(closed_fast_stop == ((wsg_device_flags(&h_dev) & WSG_FLAG(SF_FAST_STOP)) != 0u));
    wsg_conn_remove_observer(&h_dev, &conn_reader);
    h_open(&h_main, WSG_TRANSPORT_STREAM);
    calls[0] = '\0';
    h_send_bytes(&h_main, "SN?\n", 4);
    ck_assert_str_eq(calls, "B<B>"); /* removed: no read() left to call */
}
END_TEST

static wsg_gcl_observer_t gcl_a = {log_done, log_error, log_tolerated, &name_a, NULL};
static wsg_gcl_observer_t gcl_b = {log_done, log_error, log_tolerated, &name_b, NULL};
static wsg_device_observer_t device_a = {log_state, &name_a, NULL};
static wsg_device_observer_t device_b = {log_state, &name_b, NULL};

START_TEST(two_gcl_and_device_observers_are_both_called_in_order)
{
    calls[0] = '\0';
    wsg_gcl_add_observer(&h_dev, &gcl_a);
    wsg_gcl_add_observer(&h_dev, &gcl_b);
    wsg_device_add_observer(&h_dev, &device_a);
    wsg_device_add_observer(&h_dev, &device_b);
    ASK_EQ("MOVE(1,2,3)", "ERR MOVE 12");
    ck_assert_str_eq(calls, "AeBeAdBd");
    calls[0] = '\0';
    ASK_EQ("AUTOSEND(POS,0)", "ACK AUTOSEND"); /* unquoted string: tolerated */
    ck_assert_str_eq(calls, "AtBtAdBd");
    wsg_gcl_remove_observer(&h_dev, &gcl_a);
    wsg_device_remove_observer(&h_dev, &device_b);
    calls[0] = '\0';
    ASK_EQ("HOME()", "ACK HOME");
    ck_assert_str_eq(calls, "AsBd");
}
END_TEST

/* RESET's closures go unobserved: the lists are taken away and given back. */
START_TEST(observers_taken_away_hear_nothing_until_given_back)
{
    calls[0] = '\0';
    wsg_conn_add_observer(&h_dev, &conn_a);
    wsg_gcl_add_observer(&h_dev, &gcl_b);
    wsg_device_observers_t taken;
    wsg_device_take_observers(&h_dev, &taken);
    ASK_EQ("SN?", "SN=12345678");
    ck_assert_str_eq(calls, "");
    wsg_device_give_observers(&h_dev, &taken);
    ASK_EQ("SN?", "SN=12345678");
    ck_assert_str_eq(calls, "A<A>Bd");
}
END_TEST

/* --- the port's driver table --- */

/* A protocol that claims connections starting with 'X' and counts bytes. */
static size_t probe_bytes;
static bool probe_detect(uint8_t first_byte)
{
    return first_byte == 'X';
}
static void probe_open(wsg_conn_t *c)
{
    (void)c;
}
static size_t probe_input(wsg_conn_t *c, const uint8_t *bytes, size_t len)
{
    (void)c;
    (void)bytes;
    probe_bytes += len;
    return len;
}
static void probe_end_datagram(wsg_conn_t *c)
{
    (void)c;
}
static void probe_done(wsg_conn_t *c, wsg_op_t op, wsg_status_t status)
{
    (void)c;
    (void)op;
    (void)status;
}
static bool probe_busy(const wsg_conn_t *c)
{
    (void)c;
    return false;
}
static void probe_close(wsg_conn_t *c, wsg_close_reason_t why)
{
    (void)c;
    (void)why;
}
static const wsg_proto_driver_t probe_driver = {
    "probe",    probe_detect, probe_open,  probe_input, probe_end_datagram,
    probe_done, probe_busy,   probe_close, NULL,        NULL,
};

/* A port tells a connection stuck inside a message (it
 * may hold a slot forever) from one quiet between commands. */
START_TEST(a_connection_tells_a_partial_message_from_a_quiet_one)
{
    h_open_on(&h_other, &h_dev, &wsg_gcl_driver, WSG_TRANSPORT_STREAM);
    ck_assert(!wsg_conn_partial_input(&h_other.conn));
    h_send_bytes(&h_other, "SN", 2);
    ck_assert(wsg_conn_partial_input(&h_other.conn));
    ck_assert_uint_eq(wsg_conn_messages_in(&h_other.conn), 0);
    h_send_bytes(&h_other, "?\nTAG?\n", 7);
    ck_assert(!wsg_conn_partial_input(&h_other.conn));
    ck_assert_uint_eq(wsg_conn_messages_in(&h_other.conn), 2);
    h_discard(&h_other);
    static const uint8_t cut_frame[] = {0xAA, 0xAA, 0xAA, 0x21, 0xFF, 0xFF};
    h_open_on(&h_third, &h_dev, &wsg_bin_driver, WSG_TRANSPORT_STREAM);
    h_send_bytes(&h_third, cut_frame, 2);
    ck_assert(wsg_conn_partial_input(&h_third.conn)); /* a preamble begun */
    h_send_bytes(&h_third, cut_frame + 2, sizeof(cut_frame) - 2);
    ck_assert(wsg_conn_partial_input(&h_third.conn));
    ck_assert_uint_eq(wsg_conn_messages_in(&h_third.conn), 0);
    h_close(&h_third, WSG_CLOSE_ANNOUNCED);
    ck_assert(!wsg_conn_partial_input(&h_third.conn)); /* closed: holds nothing */
}
END_TEST

START_TEST(the_first_driver_that_claims_the_first_byte_serves)
{
    static const wsg_proto_driver_t *const table[] = {&probe_driver, &wsg_gcl_driver};
    wsg_conn_set_drivers(&h_dev, table, 2);
    probe_bytes = 0;
    h_open_on(&h_other, &h_dev, NULL, WSG_TRANSPORT_STREAM);
    send_line(&h_other, "XYZ");
    ck_assert_uint_eq(probe_bytes, 4);
    expect_no_line(&h_other);
    h_open_on(&h_third, &h_dev, NULL, WSG_TRANSPORT_STREAM);
    ck_assert_str_eq(ask(&h_third, "SN?"), "SN=12345678"); /* GCL takes any other byte */
    ck_assert_uint_eq(probe_bytes, 4);
}
END_TEST

START_TEST(a_reset_keeps_the_driver_table)
{
    static const wsg_proto_driver_t *const table[] = {&probe_driver};
    wsg_conn_set_drivers(&h_dev, table, 1);
    wsg_device_reset(&h_dev, h_cfg());
    probe_bytes = 0;
    h_open_on(&h_other, &h_dev, NULL, WSG_TRANSPORT_STREAM);
    send_line(&h_other, "X");
    ck_assert_uint_eq(probe_bytes, 2);
}
END_TEST

START_TEST(bytes_no_driver_claims_are_dropped)
{
    static const wsg_proto_driver_t *const table[] = {&probe_driver};
    wsg_conn_set_drivers(&h_dev, table, 1);
    probe_bytes = 0;
    h_open_on(&h_other, &h_dev, NULL, WSG_TRANSPORT_STREAM);
    send_line(&h_other, "SN?");
    expect_no_line(&h_other);
    ck_assert_uint_eq(probe_bytes, 0);
    ck_assert(wsg_conn_is_open(&h_other.conn));
    wsg_conn_set_drivers(&h_dev, NULL, 0); /* no table at all: the same */
    send_line(&h_other, "SN?");
    expect_no_line(&h_other);
    ASK_EQ("SN?", "SN=12345678"); /* a connection opened with its driver is unaffected */
}
END_TEST

Suite *session_suite(void)
{
    Suite *s = suite_create("session");
    TCase *settings = tcase_create("settings");
    tcase_add_checked_fixture(settings, h_setup, h_teardown);
    tcase_add_test(settings, pwt_clt_are_per_session);
    tcase_add_test(settings, settings_reset_on_new_session);
    tcase_add_test(settings, verbose_is_per_session);
    suite_add_tcase(s, settings);

    TCase *closing = tcase_create("closing");
    tcase_add_checked_fixture(closing, h_setup, h_teardown);
    tcase_add_test(closing, bye);
    tcase_add_test(closing, bye_ends_the_feed);
    tcase_add_test(closing, close_after_bye_keeps_running);
    tcase_add_test(closing, drop_without_bye_raises_fast_stop);
    tcase_add_test(closing, drop_without_bye_can_be_disabled);
    tcase_add_test(closing, drop_during_move_aborts_it);
    tcase_add_test(closing, datagram_peers);
    tcase_add_test(closing, datagram_with_newline);
    tcase_add_test(closing, closing_twice_is_harmless);
    suite_add_tcase(s, closing);

    TCase *multi = tcase_create("multi");
    tcase_add_checked_fixture(multi, h_setup, h_teardown);
    tcase_add_test(multi, final_line_goes_to_issuer_only);
    tcase_add_test(multi, stop_from_another_session);
    tcase_add_test(multi, queries_during_another_sessions_motion);
    tcase_add_test(multi, final_line_not_delivered_to_slot_reuser);
    tcase_add_test(multi, final_line_not_delivered_after_65536_sessions);
    tcase_add_test(multi, connections_are_the_ports);
    suite_add_tcase(s, multi);

    TCase *hook = tcase_create("hooks");
    tcase_add_checked_fixture(hook, h_setup, h_teardown);
    tcase_add_test(hook, hooks_observe_the_device);
    tcase_add_test(hook, hooks_survive_reset);
    tcase_add_test(hook, two_message_observers_hear_every_message_in_the_order_added);
    tcase_add_test(hook, a_removed_message_observer_hears_nothing_more);
    tcase_add_test(hook, a_read_comes_before_its_messages_and_a_close_is_shown);
    tcase_add_test(hook, two_gcl_and_device_observers_are_both_called_in_order);
    tcase_add_test(hook, observers_taken_away_hear_nothing_until_given_back);
    suite_add_tcase(s, hook);

    TCase *drivers = tcase_create("drivers");
    tcase_add_checked_fixture(drivers, h_setup, h_teardown);
    tcase_add_test(drivers, the_first_driver_that_claims_the_first_byte_serves);
    tcase_add_test(drivers, a_connection_tells_a_partial_message_from_a_quiet_one);
    tcase_add_test(drivers, a_reset_keeps_the_driver_table);
    tcase_add_test(drivers, bytes_no_driver_claims_are_dropped);
    suite_add_tcase(s, drivers);
    return s;
}
