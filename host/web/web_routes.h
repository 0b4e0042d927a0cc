/* SPDX-License-Identifier: BSD-3-Clause */
/* The web server's paths (docs/web.md): the page, the JSON API, and the
 * errors for anything else. */
#ifndef HOST_WEB_ROUTES_H
#define HOST_WEB_ROUTES_H

#include "web/web_internal.h"

enum MHD_Result web_routes_dispatch(const web_request_t *req);

#endif
