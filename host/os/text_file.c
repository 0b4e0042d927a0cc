/* SPDX-License-Identifier: BSD-3-Clause */
#include "text_file.h"

#include <errno.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

bool text_file_fail(const text_file_t *tf, const char *fmt, ...)
{
    char why[160];
    va_list args;
    va_start(args, fmt);
    vsnprintf(why, sizeof(why), fmt, args);
    va_end(args);
    fprintf(stderr, "wsgsim: %s:%d: %s\n", tf->path, tf->number, why);
    return false;
}

bool text_file_open(text_file_t *tf, const char *path, const char *option, size_t max_line,
                    size_t max_bytes)
{
    memset(tf, 0, sizeof(*tf));
    tf->path = path;
    tf->max_line = max_line;
    tf->max_bytes = max_bytes;
    tf->line = malloc(max_line + 2); /* room for a '\r' before the "\n" */
    tf->file = tf->line != NULL ? fopen(path, "r") : NULL;
    struct stat st;
    const char *why = tf->line == NULL ? strerror(ENOMEM) : NULL;
    if (why == NULL && tf->file == NULL) {
        why = strerror(errno);
    } else if (why == NULL && fstat(fileno(tf->file), &st) == 0 && S_ISDIR(st.st_mode)) {
        why = "it is a directory";
    }
    if (why != NULL) {
        fprintf(stderr, "wsgsim: cannot read %s file %s: %s\n", option, path, why);
        text_file_close(tf);
        return false;
    }
    return true;
}

/* One byte of the current line; false (message printed) when it is refused. */
static bool take(text_file_t *tf, int c)
{
    if (tf->max_bytes > 0 && ++tf->total > tf->max_bytes) {
        return text_file_fail(tf, "file too large (more than %zu bytes)", tf->max_bytes);
    }
    if (c == '\0') {
        return text_file_fail(tf, "NUL byte at column %zu", tf->len + 1);
    }
    if (tf->len > tf->max_line) {
        return text_file_fail(tf, "line too long (more than %zu characters)", tf->max_line);
    }
    tf->line[tf->len++] = (char)c;
    return true;
}

text_file_read_t text_file_next(text_file_t *tf)
{
    tf->len = 0;
    tf->number++;
    int c = getc(tf->file);
    bool any = c != EOF;
    for (; c != EOF && c != '\n'; c = getc(tf->file)) {
        if (!take(tf, c)) {
            return TEXT_FILE_ERROR;
        }
    }
    if (ferror(tf->file)) {
        text_file_fail(tf, "read error: %s", strerror(errno));
        return TEXT_FILE_ERROR;
    }
    if (tf->len > 0 && tf->line[tf->len - 1] == '\r') {
        tf->len--;
    }
    tf->line[tf->len] = '\0';
    if (tf->len > tf->max_line) {
        text_file_fail(tf, "line too long (more than %zu characters)", tf->max_line);
        return TEXT_FILE_ERROR;
    }
    return any ? TEXT_FILE_LINE : TEXT_FILE_END;
}

void text_file_close(text_file_t *tf)
{
    if (tf->file != NULL) {
        fclose(tf->file);
    }
    free(tf->line);
    tf->file = NULL;
    tf->line = NULL;
}
