/* SPDX-License-Identifier: BSD-3-Clause */
#include "http_host.h"

#include <arpa/inet.h>
#include <ctype.h>
#include <netinet/in.h>
#include <string.h>
#include <strings.h>

#define NAME_MAX_CHARS 253u /* a DNS name, without its trailing dot */
#define PORT_DIGITS_MAX 5u
#define LOCALHOST "localhost"

/* One name of a comma-separated list: *cursor moves past it and its comma,
 * to NULL after the last one (so "a," ends with an empty name); spaces
 * around a name are left out. False at the end of the list. */
static bool next_item(const char **cursor, const char **item, size_t *len)
{
    const char *p = *cursor;
    if (p == NULL) {
        return false;
    }
    p += strspn(p, " \t");
    size_t span = strcspn(p, ",");
    *cursor = p[span] == ',' ? p + span + 1 : NULL;
    while (span > 0 && (p[span - 1] == ' ' || p[span - 1] == '\t')) {
        span--;
    }
    *item = p;
    *len = span;
    return true;
}

static size_t without_trailing_dot(const char *name, size_t len)
{
    return len > 0 && name[len - 1] == '.' ? len - 1 : len;
}

static bool name_char(char c)
{
    return isalnum((unsigned char)c) || c == '-' || c == '.' || c == '_';
}

bool http_host_list_valid(const char *text)
{
    const char *cursor = text;
    const char *item = NULL;
    size_t len = 0;
    bool any = false;
    while (next_item(&cursor, &item, &len)) {
        bool wildcard = len == 1 && item[0] == '*';
        size_t chars = without_trailing_dot(item, len);
        if (!wildcard && (chars == 0 || chars > NAME_MAX_CHARS)) {
            return false;
        }
        for (size_t i = 0; i < len && !wildcard; i++) {
            if (!name_char(item[i])) {
                return false;
            }
        }
        any = true;
    }
    return any;
}

/* ":digits" or nothing after the host of a Host header. */
static bool port_ok(const char *rest)
{
    if (*rest == '\0') {
        return true;
    }
    size_t digits = strspn(rest + 1, "0123456789");
    return rest[0] == ':' && rest[1 + digits] == '\0' && digits <= PORT_DIGITS_MAX;
}

/* "[v6]" or "[v6]:port": an IPv6 literal. */
static bool ipv6_literal(const char *host)
{
    const char *end = strchr(host, ']');
    char text[INET6_ADDRSTRLEN];
    size_t len = end != NULL ? (size_t)(end - host - 1) : 0;
    if (end == NULL || len == 0 || len >= sizeof(text) || !port_ok(end + 1)) {
        return false;
    }
    struct in6_addr addr;
    memcpy(text, host + 1, len);
    text[len] = '\0';
    return inet_pton(AF_INET6, text, &addr) == 1;
}

static bool is_localhost(const char *name, size_t len)
{
    size_t suffix = strlen(LOCALHOST);
    if (len < suffix || strncasecmp(name + len - suffix, LOCALHOST, suffix) != 0) {
        return false;
    }
    return len == suffix || (len > suffix + 1 && name[len - suffix - 1] == '.');
}

/* name (len characters) is in one of the lists, or a list holds "*"; with
 * name NULL only "*" matches. */
static bool listed(const char *name, size_t len, const char *const *allowed, size_t count)
{
    for (size_t i = 0; i < count; i++) {
        const char *cursor = allowed[i];
        const char *item = NULL;
        size_t item_len = 0;
        while (next_item(&cursor, &item, &item_len)) {
            if (item_len == 1 && item[0] == '*') {
                return true;
            }
            item_len = without_trailing_dot(item, item_len);
            if (name != NULL && item_len == len && strncasecmp(item, name, len) == 0) {
                return true;
            }
        }
    }
    return false;
}

bool http_host_allowed(const char *host, const char *const *allowed, size_t count)
{
    if (host[0] == '[') {
        return ipv6_literal(host) || listed(NULL, 0, allowed, count);
    }
    size_t len = strcspn(host, ":");
    if (!port_ok(host + len) || len > NAME_MAX_CHARS + 1u) {
        return listed(NULL, 0, allowed, count); /* no name: only "*" takes it */
    }
    char name[NAME_MAX_CHARS + 2u];
    memcpy(name, host, len);
    name[len] = '\0';
    len = without_trailing_dot(name, len);
    name[len] = '\0';
    struct in_addr v4;
    if (inet_pton(AF_INET, name, &v4) == 1 || is_localhost(name, len)) {
        return true;
    }
    return listed(name, len, allowed, count);
}
