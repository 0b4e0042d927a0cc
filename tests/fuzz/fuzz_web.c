/* SPDX-License-Identifier: BSD-3-Clause */
/* libFuzzer target: arbitrary requests through the web server's routes
 * (host/web/web_routes.c and every route behind it) with their JSON bodies
 * (cJSON), against the real host on the paused simulated clock, without
 * sockets (fuzz_mhd.h stands in for libmicrohttpd and checks every reply).
 *
 * Input layout: byte 0 picks the number of devices (bits 0-1: 1..4); then
 * requests separated by 0xFF (a byte no URL or JSON text holds), each as
 * fuzz_mhd.h describes it. */
#include <stdlib.h>

#include "fuzz_host.h"
#include "fuzz_mhd.h"

#define SEPARATOR 0xffu

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size == 0) {
        return 0;
    }
    char devices[2] = {(char)('1' + (data[0] & 3u)), '\0'};
    char *argv[] = {"wsgsim", "--no-udp", "--devices", devices, NULL};
    host_options_t *opts = fuzz_host_options(4, argv);
    if (opts == NULL) {
        abort();
    }
    web_app_t app; /* what the server keeps for its routes */
    fuzz_mhd_app_start(&app, opts);
    size_t first = 1;
    for (size_t i = 1; i <= size; i++) {
        if (i == size || data[i] == SEPARATOR) {
            fuzz_mhd_request(&app, data + first, i - first, "");
            first = i + 1;
        }
    }
    fuzz_mhd_app_stop(&app);
    return 0;
}
