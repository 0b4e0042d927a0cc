/* SPDX-License-Identifier: BSD-3-Clause */
/* The record file's lines (docs/simctl.md, "Record format"), for every
 * program that writes one: wsgsim's --record (record.c) and the recording
 * proxy wsgproxy. A line is "sim_s wall_s channel dir text", the text
 * escaped; the header names the format's version. */
#ifndef HOST_RECORD_FILE_H
#define HOST_RECORD_FILE_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

/* 2: directions from the client's side, and the device's state sampled. */
#define RECORD_FILE_VERSION 2

/* Opens path with fopen()'s mode ("w" truncates, "a" appends) and the
 * stdio buffering `buffering` (_IOLBF, _IOFBF); a file that starts empty
 * gets the header. NULL with errno set. */
FILE *record_file_open(const char *path, const char *mode, int buffering);
/* One line: `sim_us` as sim_s, the wall clock read now, the channel, the
 * direction ('>' from a client, '<' to it, '=' a state sample) and the
 * text, its line terminators taken off, a backslash written "\\" and any
 * byte outside printable ASCII "\xNN". */
void record_file_put(FILE *out, uint64_t sim_us, const char *channel, char direction,
                     const char *text, size_t len);

#endif
