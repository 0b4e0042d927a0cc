/* SPDX-License-Identifier: BSD-3-Clause */
/* libFuzzer target: the /user/ store's routes and the script routes that
 * name store files (host/web/web_store.c, web_script.c): file names in the
 * URL, JSON bodies, Run and the startup choice, against the real host with
 * a store on disk in the shipped units' layout (the save file in the store,
 * here under a .lua name), without sockets (fuzz_mhd.h).
 *
 * The store is made afresh for every input: a script, a FIFO, the save
 * file and a file that is no script; beside the store, a Lua file whose
 * text (a new one for every input) no reply may quote. Besides fuzz_mhd.h's rules, every input must
 * leave the save file as it was, and nothing may block (a FIFO opened for reading would:
 * libFuzzer's -timeout reports it).
 *
 * Input layout: requests separated by 0xFF, each as fuzz_mhd.h describes
 * it, its URL after "/api/devices/0/" ("files/x.lua", "script/run", ...). */
#include <dirent.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "fuzz_host.h"
#include "fuzz_mhd.h"

#define SEPARATOR 0xffu
#define SAVED "[device]\n; the save file\n"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static char top[PATH_MAX];   /* the store's parent: the file outside */
static char store[PATH_MAX]; /* the /user/ store */
static char saved[PATH_MAX]; /* --save-file, in the store */
/* The text of the file outside, new for every input: the fuzzer cannot
 * learn it from one input (the check's comparison) and write it in the next. */
static char secret[32];

/* dir/name into out (PATH_MAX bytes). */
static void join(char *out, const char *dir, const char *name)
{
    if ((size_t)snprintf(out, PATH_MAX, "%s/%s", dir, name) >= PATH_MAX) {
        abort();
    }
}

static void write_file(const char *dir, const char *name, const char *text)
{
    char path[PATH_MAX];
    join(path, dir, name);
    FILE *f = fopen(path, "w");
    if (f == NULL || fputs(text, f) < 0 || fclose(f) != 0) {
        abort();
    }
}

/* Everything the last input left in the store goes. */
static void empty_store(void)
{
    DIR *d = opendir(store);
    struct dirent *e;
    while (d != NULL && (e = readdir(d)) != NULL) {
        char path[PATH_MAX];
        if (strcmp(e->d_name, ".") != 0 && strcmp(e->d_name, "..") != 0 &&
            (size_t)snprintf(path, sizeof(path), "%s/%s", store, e->d_name) < sizeof(path)) {
            (void)unlink(path);
        }
    }
    if (d != NULL) {
        closedir(d);
    }
}

static void remove_store(void)
{
    char path[PATH_MAX];
    empty_store();
    (void)rmdir(store);
    join(path, top, "secret.lua");
    (void)unlink(path);
    (void)rmdir(top);
}

static void make_store(void)
{
    if (top[0] == '\0') {
        const char *tmp = getenv("TMPDIR");
        char name[64];
        snprintf(name, sizeof(name), "wsgsim-fuzz-store-%ld", (long)getpid());
        join(top, tmp != NULL ? tmp : "/tmp", name);
        join(store, top, "scripts");
        join(saved, store, "saved.lua");
        if ((mkdir(top, 0700) != 0 && access(top, W_OK) != 0) ||
            (mkdir(store, 0700) != 0 && access(store, W_OK) != 0)) {
            abort();
        }
        atexit(remove_store);
    }
    static uint64_t state;
    state = state * 6364136223846793005u + 1442695040888963407u + (uint64_t)time(NULL);
    snprintf(secret, sizeof(secret), "sk-%016llx", (unsigned long long)state);
    char text[3 * sizeof(secret) + 16];
    snprintf(text, sizeof(text), "print('%s')\n'%s\n", secret, secret);
    write_file(top, "secret.lua", text);
    empty_store();
    write_file(store, "ok.lua", "print('ok')\n");
    write_file(store, "notes.txt", "not a script\n");
    write_file(store, "saved.lua", SAVED);
    char fifo[PATH_MAX];
    join(fifo, store, "pipe.lua");
    if (mkfifo(fifo, 0600) != 0) {
        abort();
    }
}

static void check_saved(void)
{
    char text[sizeof(SAVED) + 1];
    FILE *f = fopen(saved, "r");
    size_t n = f != NULL ? fread(text, 1, sizeof(text), f) : 0u;
    if (f == NULL || fclose(f) != 0 || n != sizeof(SAVED) - 1u || memcmp(text, SAVED, n) != 0) {
        abort(); /* the store wrote or deleted wsgsim's own file */
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    make_store();
    char *argv[] = {"wsgsim", "--no-udp", "--script-dir", store, "--save-file", saved, NULL};
    host_options_t *opts = fuzz_host_options(6, argv);
    if (opts == NULL) {
        abort();
    }
    web_app_t app; /* what the server keeps for its routes */
    fuzz_mhd_app_start(&app, opts);
    fuzz_mhd_forbid(secret);
    size_t first = 0;
    for (size_t i = 0; i <= size; i++) {
        if (i == size || data[i] == SEPARATOR) {
            fuzz_mhd_request(&app, data + first, i - first, "/api/devices/0/");
            check_saved();
            first = i + 1;
        }
    }
    fuzz_mhd_forbid(NULL);
    fuzz_mhd_app_stop(&app);
    return 0;
}
