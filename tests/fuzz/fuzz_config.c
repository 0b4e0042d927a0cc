/* SPDX-License-Identifier: BSD-3-Clause */
/* libFuzzer target: the input is a --config file (INI, read by libinih
 * through host/os/text_file.c and host/config/config_file.c), given to options_parse()
 * as `wsgsim --config FILE`. A file that is accepted starts the host (its
 * [device.N] sections make the fleet), and then must survive the web page's
 * Save (host/config/config_file_save.c, which rewrites it line by line) of device
 * 0's settings, a tag and a motion setting changed as on the page: when the
 * save succeeds (it may refuse settings another model of the file cannot
 * take),
 *   - the saved file is accepted again, and device 0 starts with the saved
 *     settings;
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

/* The [physics] scene is read by MuJoCo, not by wsgsim (and a scene that
 * does not load stops the start on purpose): the file's keys are parsed,
 * the host starts in the built-in world. */
static const host_options_t *parse(const char *path)
{
    char *argv[] = {"wsgsim", "--no-udp", "--config", (char *)path, NULL};
    host_options_t *opts = fuzz_host_options(4, argv);
    if (opts != NULL) {
        opts->physics = HOST_PHYSICS_BUILTIN;
    }
    return opts;
}

/* What the page changes before its Save: a setting of each kind the save
 * writes (a tag, a motion setting every model takes), so that the file
 * must carry them over the values it had. The tag holds " ;", libinih's
 * inline comment, as any client may set it (binary 0x51). */
#define SAVED_TAG "fuzz ;saved"
#define SAVED_CLT_MM 1.5f

/* Starts the host from opts, saves device 0's settings to path (changed as
 * the page would when change is set; false: the save refused them) and
 * reads the file back into out (*len bytes). */
static bool start_and_save(const host_options_t *opts, const char *path, bool change, char *out,
                           size_t *len)
{
    fuzz_host_start(opts);
    wsg_config_t cfg = *wsg_device_snapshot(&fleet_gripper(fuzz_host_fleet(), 0)->device)->config;
    if (!change && (strcmp(cfg.tag, SAVED_TAG) != 0 || cfg.default_clt_mm != SAVED_CLT_MM)) {
        fprintf(stderr, "fuzz_config: the saved settings are not what the device starts with\n");
        abort();
    }
    if (change) {
        snprintf(cfg.tag, sizeof(cfg.tag), "%s", SAVED_TAG);
        cfg.default_clt_mm = SAVED_CLT_MM;
    }
    char why[256];
    bool saved_ok = config_file_save(opts->config, path, 0, &cfg, NULL, why, sizeof(why));
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
    if (opts != NULL && start_and_save(opts, path, true, saved[0], &first)) {
        opts = parse(path);
        if (opts == NULL) {
            fprintf(stderr, "fuzz_config: the saved file is refused\n");
            abort();
        }
        if (!start_and_save(opts, path, false, saved[1], &second) || first != second ||
            memcmp(saved[0], saved[1], first) != 0) {
            fprintf(stderr, "fuzz_config: saving the saved file failed or changed it\n");
            abort();
        }
    }
    fuzz_host_close_file();
    return 0;
}
