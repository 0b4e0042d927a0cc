/* SPDX-License-Identifier: BSD-3-Clause */
/* libFuzzer target: the input is a --config file (INI, read by libinih
 * through host/text_file.c and host/config_file.c), given to options_parse()
 * as `wsgsim --config FILE`. A file that is accepted starts the host (its
 * [device.N] sections make the fleet), and then must survive the web page's
 * Save (host/config_file_save.c, which rewrites it line by line): when
 * saving device 0's settings in force succeeds (it may refuse settings
 * another model of the file cannot take),
 *   - the saved file is accepted again;
 *   - saving again from the reloaded file succeeds and writes the same bytes. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "config_file.h"
#include "fleet.h"
#include "fuzz_host.h"

#define SAVED_MAX (1u << 20)

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static char saved[2][SAVED_MAX];

static const host_options_t *parse(const char *path)
{
    char *argv[] = {"wsgsim", "--no-udp", "--config", (char *)path, NULL};
    return fuzz_host_options(4, argv);
}

/* Starts the host from opts, saves device 0 to path (false: refused) and
 * reads the file back into out (*len bytes). */
static bool start_and_save(const host_options_t *opts, const char *path, char *out, size_t *len)
{
    fuzz_host_start(opts);
    const wsg_config_t *cfg = wsg_device_snapshot(&fleet_gripper(0)->device)->config;
    char why[256];
    bool saved_ok = config_file_save(path, 0, cfg, why, sizeof(why));
    fuzz_host_stop();
    FILE *f = fopen(path, "rb");
    if (f == NULL) {
        abort();
    }
    *len = fread(out, 1, SAVED_MAX, f);
    fclose(f);
    return saved_ok;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    const char *path = fuzz_host_file(data, size);
    const host_options_t *opts = parse(path);
    size_t first = 0;
    size_t second = 0;
    if (opts != NULL && start_and_save(opts, path, saved[0], &first)) {
        opts = parse(path);
        if (opts == NULL) {
            fprintf(stderr, "fuzz_config: the saved file is refused\n");
            abort();
        }
        if (!start_and_save(opts, path, saved[1], &second) || first != second ||
            memcmp(saved[0], saved[1], first) != 0) {
            fprintf(stderr, "fuzz_config: saving the saved file failed or changed it\n");
            abort();
        }
    }
    fuzz_host_close_file();
    return 0;
}
