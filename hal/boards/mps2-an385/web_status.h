/* SPDX-License-Identifier: BSD-3-Clause */
/* The lwIP image's status page, served by lwIP's httpd on port 80:
 *   GET /                      a small page that polls the state below
 *   GET /api/devices/0/state   the device's state as JSON, a subset of the
 *                              host's /api/devices/{id}/state (same names)
 * Every response is built by fs_open_custom (LWIP_HTTPD_CUSTOM_FILES) from
 * flash or from a static slot per connection: no heap. See docs/web-board.md. */
#ifndef WEB_STATUS_H
#define WEB_STATUS_H

/* Starts httpd's listener; call once, after lwip_init(). */
void web_status_init(void);

#endif
