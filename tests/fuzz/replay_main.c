/* SPDX-License-Identifier: BSD-3-Clause */
/* Replays fuzz inputs through the fuzz target without libFuzzer, so that the
 * seed corpus and every regression input run in `make check` with the
 * project's compiler (and under SAN=1 with ASan+UBSan).
 * usage: fuzz_replay FILE|DIR...   exit status 0 when every input ran. */
#define _DEFAULT_SOURCE /* scandir, alphasort */
#include <dirent.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#define INPUT_MAX (1u << 20)

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static unsigned long replayed;

static int replay_file(const char *path)
{
    static uint8_t buf[INPUT_MAX];
    FILE *f = fopen(path, "rb");
    if (f == NULL) {
        fprintf(stderr, "fuzz_replay: cannot open %s\n", path);
        return 1;
    }
    size_t n = fread(buf, 1, sizeof(buf), f);
    fclose(f);
    LLVMFuzzerTestOneInput(buf, n);
    replayed++;
    return 0;
}

static int replay_path(const char *path);

static int replay_dir(const char *path)
{
    struct dirent **names = NULL;
    int count = scandir(path, &names, NULL, alphasort);
    if (count < 0) {
        fprintf(stderr, "fuzz_replay: cannot read %s\n", path);
        return 1;
    }
    int failed = 0;
    for (int i = 0; i < count; i++) {
        if (names[i]->d_name[0] != '.') {
            char child[4096];
            snprintf(child, sizeof(child), "%s/%s", path, names[i]->d_name);
            failed |= replay_path(child);
        }
        free(names[i]);
    }
    free(names);
    return failed;
}

static int replay_path(const char *path)
{
    struct stat st;
    if (stat(path, &st) != 0) {
        fprintf(stderr, "fuzz_replay: no such input %s\n", path);
        return 1;
    }
    return S_ISDIR(st.st_mode) ? replay_dir(path) : replay_file(path);
}

int main(int argc, char **argv)
{
    int failed = 0;
    for (int i = 1; i < argc; i++) {
        failed |= replay_path(argv[i]);
    }
    printf("fuzz_replay: %lu inputs replayed\n", replayed);
    return failed != 0 || replayed == 0 ? 1 : 0;
}
