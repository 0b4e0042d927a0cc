/* SPDX-License-Identifier: BSD-3-Clause */
#include "script_options.h"

#include <errno.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "config_file.h"
#include "script.h"

/* "/user/NAME" is NAME in the store. */
static bool startup_path(const host_options_t *opts, char *out, size_t cap)
{
    if (strncmp(opts->script, "/user/", 6) != 0) {
        return (size_t)snprintf(out, cap, "%s", opts->script) < cap;
    }
    if (opts->script_dir == NULL) {
        return false;
    }
    return (size_t)snprintf(out, cap, "%s/%s", opts->script_dir, opts->script + 6) < cap;
}

/* A startup file that is missing or unreadable is a start error. */
static bool check_startup(const host_options_t *opts, const char *script)
{
    struct stat st;
    char path[4096];
    host_options_t one = *opts;
    one.script = script;
    if (!startup_path(&one, path, sizeof(path))) {
        fprintf(stderr, "wsgsim: --script %s: /user/ names need --script-dir\n", script);
        return false;
    }
    if (strncmp(script, "/user/", 6) == 0 && !script_store_name_ok(script + 6)) {
        fprintf(stderr, "wsgsim: --script %s: not a store name (/user/NAME.lua)\n", script);
        return false;
    }
    errno = 0;
    if (stat(path, &st) != 0 || !S_ISREG(st.st_mode) || access(path, R_OK) != 0) {
        fprintf(stderr, "wsgsim: --script %s: %s\n", script,
                errno != 0 ? strerror(errno) : "not a readable file");
        return false;
    }
    return true;
}

/* The files the user names (--script, a --config file) must be there; a
 * startup script the saved settings chose starts the device anyway, which
 * reports it failed: the device boots whatever its store holds. */
static bool startup_ok(const host_options_t *opts, unsigned index, const char *script)
{
    return config_file_startup_saved(opts->config, index, script) || check_startup(opts, script);
}

bool script_options_check(const host_options_t *opts)
{
    struct stat st;
    if (opts->script_dir != NULL && (stat(opts->script_dir, &st) != 0 || !S_ISDIR(st.st_mode))) {
        fprintf(stderr, "wsgsim: --script-dir %s: not a directory\n", opts->script_dir);
        return false;
    }
    if (opts->script != NULL && !startup_ok(opts, 0, opts->script)) {
        return false;
    }
    /* [device.N] script of the configuration file */
    for (unsigned i = 0; i < config_file_devices(opts->config); i++) {
        const char *script = config_file_device_script(opts->config, i, NULL);
        if (script != NULL && !startup_ok(opts, i, script)) {
            return false;
        }
    }
    return true;
}

bool script_options_store(const host_options_t *opts, char *out, size_t cap)
{
    if (opts->script_dir != NULL) {
        return (size_t)snprintf(out, cap, "%s", opts->script_dir) < cap;
    }
    if (opts->script == NULL || strncmp(opts->script, "/user/", 6) == 0) {
        return false; /* /user/ is the store's name, no host directory */
    }
    const char *slash = strrchr(opts->script, '/');
    if (slash == NULL) {
        return (size_t)snprintf(out, cap, ".") < cap;
    }
    int len = (int)(slash - opts->script);
    return (size_t)snprintf(out, cap, "%.*s", len > 0 ? len : 1, opts->script) < cap;
}

bool script_options_enabled(const host_options_t *opts)
{
    return opts->script != NULL || opts->script_dir != NULL;
}
