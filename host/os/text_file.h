/* SPDX-License-Identifier: BSD-3-Clause */
/* Reads the text files wsgsim is given (--config, --scenario) line by line,
 * each line whole: a directory, a NUL byte, a line longer than the caller's
 * limit or a file larger than its limit is an error that names file:line,
 * never a silently split line or an endless read. */
#ifndef HOST_TEXT_FILE_H
#define HOST_TEXT_FILE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>

typedef struct {
    FILE *file;
    const char *path;
    size_t max_line;  /* longest accepted line, without its terminator */
    size_t max_bytes; /* the whole file; 0: no limit */
    size_t total;     /* bytes read so far */
    int number;       /* the current line, from 1 */
    char *line;       /* the current line without "\n" or "\r\n" (NUL-terminated) */
    size_t len;
} text_file_t;

typedef enum {
    TEXT_FILE_LINE,  /* tf->line holds line tf->number */
    TEXT_FILE_END,   /* no more lines */
    TEXT_FILE_ERROR, /* "wsgsim: FILE:LINE: reason" was printed */
} text_file_read_t;

/* Opens path for reading; option (e.g. "--config") names it in the message
 * printed when it cannot be read or is a directory. */
bool text_file_open(text_file_t *tf, const char *path, const char *option, size_t max_line,
                    size_t max_bytes);
text_file_read_t text_file_next(text_file_t *tf);
void text_file_close(text_file_t *tf);
/* Prints "wsgsim: FILE:LINE: reason" for the current line; returns false. */
bool text_file_fail(const text_file_t *tf, const char *fmt, ...)
    __attribute__((format(printf, 2, 3)));

#endif
