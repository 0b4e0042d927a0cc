/* SPDX-License-Identifier: BSD-3-Clause */
/* The page's files, built into the binary: web/, turned into one table by
 * mk/web_assets.py (build/gen/web_assets.c). Debian's dygraphs is served
 * from its installed files (web_static.c). */
#ifndef HOST_WEB_ASSETS_H
#define HOST_WEB_ASSETS_H

#include <stddef.h>

typedef struct {
    const char *name;         /* "index.html", "app.js", "style.css" */
    const char *content_type; /* "text/javascript; charset=utf-8", ... */
    const unsigned char *bytes;
    size_t len;
} web_asset_t;

/* Ends with an entry whose name is NULL. */
extern const web_asset_t web_assets[];

#endif
