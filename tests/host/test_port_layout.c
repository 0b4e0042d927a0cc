/* SPDX-License-Identifier: BSD-3-Clause */
/* The fleet's port layout (host/port/port_layout.c): with the
 * default binary ports no two listening ports of any device collide, nor a
 * binary reply port with a port a device listens on, for every allowed
 * number of devices. */
#include <check.h>
#include <stdint.h>
#include <stdio.h>

#include "host_suites.h"
#include "options.h"
#include "port_layout.h"

#define PORTS 65536u

/* Which check last claimed each port: a stamp per check, no clearing. */
static uint32_t udp_claimed[PORTS];
static uint32_t tcp_claimed[PORTS];
static uint32_t stamp;
static char problem[160]; /* the first collision found, for the failure message */

/* Claims port for device i; false (with the problem) when another has it. */
static bool claim(uint32_t *claimed, long port, const char *what, unsigned i)
{
    if (port == 0) {
        return true; /* a free port, the kernel's choice */
    }
    if (port < 0 || port >= (long)PORTS || claimed[port] == stamp) {
        snprintf(problem, sizeof(problem), "device %u: %s port %ld out of range or taken", i, what,
                 port);
        return false;
    }
    claimed[port] = stamp;
    return true;
}

/* Every device of plan fits and no port is used twice. Plain checks in the
 * loop: a Check assertion per port would cost more than the layout. */
static bool layout_is_clear(const port_plan_t *plan)
{
    stamp++;
    for (unsigned i = 0; i < plan->devices; i++) {
        port_layout_t p;
        if (!port_layout_of(plan, i, &p)) {
            snprintf(problem, sizeof(problem), "device %u does not fit", i);
            return false;
        }
        if (!claim(tcp_claimed, p.tcp, "tcp", i) || !claim(udp_claimed, p.udp, "udp", i) ||
            !claim(udp_claimed, p.binary, "binary udp", i) ||
            !claim(udp_claimed, p.reply, "reply", i)) {
            return false;
        }
    }
    return true;
}

static port_plan_t defaults(unsigned n)
{
    return (port_plan_t){1000, 1000, PORT_LAYOUT_BINARY_DEFAULT, PORT_LAYOUT_REPLY_DEFAULT,
                         true, n};
}

START_TEST(the_default_layout_never_collides)
{
    for (unsigned n = 1; n <= HOST_DEVICES_MAX; n++) {
        port_plan_t plan = defaults(n);
        ck_assert_msg(layout_is_clear(&plan), "N=%u: %s", n, problem);
    }
}
END_TEST

/* Whatever the GCL ports (another default, --udp-port, free ports), the
 * default binary pairs keep clear of them. */
START_TEST(the_binary_pairs_avoid_any_gcl_range)
{
    static const int udp_bases[] = {0, 1, 999, 1200, 1499, 1500, 1501, 2000, 2500, 11000};
    for (size_t b = 0; b < sizeof(udp_bases) / sizeof(udp_bases[0]); b++) {
        for (unsigned n = 1; n <= HOST_DEVICES_MAX; n++) {
            port_plan_t plan = defaults(n);
            plan.udp_base = udp_bases[b];
            ck_assert_msg(layout_is_clear(&plan), "udp %d, N=%u: %s", udp_bases[b], n, problem);
        }
    }
}
END_TEST

START_TEST(device_zero_keeps_the_real_devices_ports)
{
    for (unsigned n = 1; n <= 500; n++) {
        port_plan_t plan = defaults(n);
        port_layout_t p;
        ck_assert(port_layout_of(&plan, 0, &p));
        ck_assert_int_eq(p.tcp, 1000);
        ck_assert_int_eq(p.udp, 1000);
        ck_assert_int_eq(p.binary, 1500);
        ck_assert_int_eq(p.reply, 1501);
    }
    port_plan_t two = defaults(2);
    port_layout_t p;
    ck_assert(port_layout_of(&two, 1, &p));
    ck_assert_int_eq(p.binary, 1502);
    ck_assert_int_eq(p.reply, 1503);
    port_plan_t fleet = defaults(1024); /* GCL UDP 1000-2023: the pairs start at 2024 */
    ck_assert(port_layout_of(&fleet, 0, &p));
    ck_assert_int_eq(p.binary, 2024);
    ck_assert_int_eq(p.reply, 2025);
    ck_assert(port_layout_of(&fleet, 1023, &p));
    ck_assert_int_eq(p.reply, 2024 + 2 * 1023 + 1);
}
END_TEST

START_TEST(given_binary_ports_are_offset_as_configured)
{
    port_plan_t plan = defaults(3);
    plan.binary_base = 1500;
    plan.reply_base = 2500;
    port_layout_t p;
    ck_assert(port_layout_of(&plan, 2, &p));
    ck_assert_int_eq(p.binary, 1502);
    ck_assert_int_eq(p.reply, 2502);
    plan.reply_base = 0; /* the sender's own port */
    ck_assert(port_layout_of(&plan, 2, &p));
    ck_assert_int_eq(p.reply, 0);
    plan.binary_base = 0; /* off */
    ck_assert(port_layout_of(&plan, 2, &p));
    ck_assert_int_eq(p.binary, 0);
}
END_TEST

START_TEST(ports_past_65535_are_refused)
{
    port_plan_t plan = defaults(3);
    plan.tcp_base = 65534;
    port_layout_t p;
    ck_assert(port_layout_of(&plan, 1, &p));
    ck_assert(!port_layout_of(&plan, 2, &p));
    ck_assert_int_eq(p.tcp, 65536);
    plan = defaults(2);
    plan.binary_base = 65535; /* given: device 1 would need 65536 */
    ck_assert(!port_layout_of(&plan, 1, &p));
    ck_assert_int_eq(p.binary, 65536);
}
END_TEST

Suite *port_layout_suite(void)
{
    Suite *s = suite_create("port_layout");
    TCase *tc = tcase_create("fleet");
    tcase_set_timeout(tc, 60);
    tcase_add_test(tc, the_default_layout_never_collides);
    tcase_add_test(tc, the_binary_pairs_avoid_any_gcl_range);
    tcase_add_test(tc, device_zero_keeps_the_real_devices_ports);
    tcase_add_test(tc, given_binary_ports_are_offset_as_configured);
    tcase_add_test(tc, ports_past_65535_are_refused);
    suite_add_tcase(s, tc);
    return s;
}
