/* SPDX-License-Identifier: BSD-3-Clause */
/* The server's own sockets (host/os/net.c): a datagram socket net_listen()
 * opened is its net_t's own address, on loopback, and no other net_t's; a
 * TCP listener's port number is not (a peer's UDP port may carry it). */
#include <arpa/inet.h>
#include <check.h>
#include <netinet/in.h>
#include <string.h>
#include <unistd.h>

#include "host_suites.h"
#include "net.h"

static struct sockaddr_storage loopback(int port)
{
    struct sockaddr_storage ss;
    memset(&ss, 0, sizeof(ss));
    struct sockaddr_in *in = (struct sockaddr_in *)&ss;
    in->sin_family = AF_INET;
    in->sin_port = htons((uint16_t)port);
    in->sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    return ss;
}

START_TEST(a_listening_socket_is_its_nets_own_address_only)
{
    net_t mine, other;
    net_init(&mine);
    net_init(&other);
    int fd = net_listen(&mine, SOCK_DGRAM, "127.0.0.1", 0);
    ck_assert_int_ge(fd, 0);
    int port = net_local_port(fd);
    struct sockaddr_storage self = loopback(port);
    struct sockaddr_storage next_port = loopback(port == 65535 ? 1 : port + 1);
    ck_assert(net_is_own_address(&mine, &self));
    ck_assert(!net_is_own_address(&mine, &next_port));
    ck_assert(!net_is_own_address(&other, &self));
    close(fd);
}
END_TEST

/* Before, a UDP peer whose ephemeral port happened to have the number of
 * the GCL TCP port was taken for the server itself and never answered. */
START_TEST(a_tcp_listeners_port_number_is_not_an_own_address)
{
    net_t mine;
    net_init(&mine);
    int fd = net_listen(&mine, SOCK_STREAM, "127.0.0.1", 0);
    ck_assert_int_ge(fd, 0);
    struct sockaddr_storage same_number = loopback(net_local_port(fd));
    ck_assert(!net_is_own_address(&mine, &same_number));
    close(fd);
}
END_TEST

Suite *net_suite(void)
{
    Suite *s = suite_create("net");
    TCase *tc = tcase_create("own_sockets");
    tcase_add_test(tc, a_listening_socket_is_its_nets_own_address_only);
    tcase_add_test(tc, a_tcp_listeners_port_number_is_not_an_own_address);
    suite_add_tcase(s, tc);
    return s;
}
