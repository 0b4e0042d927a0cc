/* SPDX-License-Identifier: BSD-3-Clause */
/* The file table lwIP's fs.c includes (HTTPD_FSDATA_FILE in lwipopts.h):
 * empty, because web_status.c answers every path through fs_open_custom and
 * lwIP's demo pages must not end up in flash. */
#ifndef WEB_STATUS_FSDATA_H
#define WEB_STATUS_FSDATA_H

#define FS_ROOT NULL
#define FS_NUMFILES 0

#endif
