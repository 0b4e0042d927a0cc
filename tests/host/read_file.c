/* SPDX-License-Identifier: BSD-3-Clause */
/* What the host suites read back from the files a module wrote. */
#include <stdio.h>

#include "host_suites.h"

const char *t_read_all(const char *path)
{
    static char text[512];
    FILE *f = fopen(path, "r");
    ck_assert_ptr_nonnull(f);
    size_t n = fread(text, 1, sizeof(text) - 1, f);
    text[n] = '\0';
    fclose(f);
    return text;
}
