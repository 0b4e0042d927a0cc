/* SPDX-License-Identifier: BSD-3-Clause */
/* lwIP configuration of the Ethernet image: NO_SYS (bare metal, one main
 * loop, no interrupts touching lwIP), IPv4 with ARP, ICMP, UDP and TCP over
 * the raw API; no sockets, netconn, DHCP, DNS or IPv6. Sized for a handful
 * of GCL connections within the 64 KiB RAM budget. */
#ifndef LWIPOPTS_H
#define LWIPOPTS_H

#define NO_SYS 1
#define SYS_LIGHTWEIGHT_PROT 0 /* lwIP runs only in the main loop */
#define LWIP_SOCKET 0
#define LWIP_NETCONN 0
#define LWIP_SINGLE_NETIF 1

/* Memory: lwIP's own static pools; never the C library's malloc. */
#define MEM_LIBC_MALLOC 0
#define MEMP_MEM_MALLOC 0
#define MEM_ALIGNMENT 4
#define MEM_SIZE (10 * 1024)
#define PBUF_POOL_SIZE 8
#define MEMP_NUM_PBUF 8
#define MEMP_NUM_UDP_PCB 2
/* GCL_TCP_MAX_CONNECTIONS plus one to refuse politely, plus the status
 * page's MEMP_NUM_PARALLEL_HTTPD_CONNS */
#define MEMP_NUM_TCP_PCB 7
#define MEMP_NUM_TCP_PCB_LISTEN 2 /* GCL and HTTP */
#define MEMP_NUM_TCP_SEG 24
#define MEMP_NUM_SYS_TIMEOUT 8
#define MEMP_NUM_ARP_QUEUE 4

/* Protocols */
#define LWIP_IPV4 1
#define LWIP_IPV6 0
#define LWIP_ARP 1
#define LWIP_ETHERNET 1
#define LWIP_ICMP 1
#define LWIP_RAW 0
#define LWIP_UDP 1
#define LWIP_TCP 1
#define LWIP_DHCP 0
#define LWIP_AUTOIP 0
#define LWIP_IGMP 0
#define LWIP_DNS 0
#define IP_REASSEMBLY 0
#define IP_FRAG 0
#define ETHARP_SUPPORT_STATIC_ENTRIES 0
#define LWIP_NETIF_LINK_CALLBACK 0
#define LWIP_NETIF_STATUS_CALLBACK 0

/* TCP: GCL lines are short; a few segments in flight are plenty. */
#define TCP_MSS 1460
#define TCP_WND (2 * TCP_MSS)
#define TCP_SND_BUF (2 * TCP_MSS)
#define TCP_SND_QUEUELEN 16
#define LWIP_TCP_KEEPALIVE 1 /* notice a client that vanished */
#define TCP_KEEPIDLE_DEFAULT 10000
#define TCP_KEEPINTVL_DEFAULT 2000
#define TCP_KEEPCNT_DEFAULT 5

/* The LAN9118 has no checksum offload: lwIP computes them all. */
#define CHECKSUM_GEN_IP 1
#define CHECKSUM_GEN_UDP 1
#define CHECKSUM_GEN_TCP 1
#define CHECKSUM_CHECK_IP 1
#define CHECKSUM_CHECK_UDP 1
#define CHECKSUM_CHECK_TCP 1

#define LWIP_STATS 0

/* The status page (web_status.c) through lwIP's httpd: GET only, one
 * request per connection, every response built by fs_open_custom with its
 * headers included. Its connection states come from their own static pool,
 * so a browser never takes lwIP heap or PCBs from the GCL clients: httpd
 * listens at TCP_PRIO_MIN, the GCL server at TCP_PRIO_NORMAL, and lwIP
 * reclaims a page's PCB for a GCL client when the pool runs dry. */
#define HTTPD_SERVER_PORT 80
#define HTTPD_USE_MEM_POOL 1
#define MEMP_NUM_PARALLEL_HTTPD_CONNS 2
#define LWIP_HTTPD_KILL_OLD_ON_CONNECTIONS_EXCEEDED 1 /* an idle browser socket */
#define LWIP_HTTPD_CUSTOM_FILES 1
#define LWIP_HTTPD_DYNAMIC_HEADERS 0
#define LWIP_HTTPD_SUPPORT_EXTSTATUS 1 /* 400 and 501 pages, not a silent close */
#define LWIP_HTTPD_SUPPORT_V09 0
#define HTTPD_FSDATA_FILE "web_status_fsdata.h"
/* A request split over more segments than this gets a 400: a slow client
 * holds at most this many of the PBUF_POOL_SIZE receive buffers. */
#define LWIP_HTTPD_REQ_QUEUELEN 2
/* The state's JSON lives in a slot freed when httpd closes the file, which
 * may be before the client acknowledged it: httpd copies every response
 * into lwIP's heap rather than sending from the slot. */
#define HTTP_IS_DATA_VOLATILE(hs) TCP_WRITE_FLAG_COPY

#endif
