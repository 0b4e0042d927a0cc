/* SPDX-License-Identifier: BSD-3-Clause */
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <sys/epoll.h>
#include <time.h>

#include "bench.h"

double now_us(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec * 1e6 + (double)ts.tv_nsec / 1e3;
}

void die(const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    fputs("wsgbench: ", stderr);
    vfprintf(stderr, fmt, ap);
    fputc('\n', stderr);
    va_end(ap);
    server_kill_all();
    exit(1);
}

void samples_init(samples_t *s, size_t cap)
{
    s->v = malloc(cap * sizeof(double));
    s->n = 0;
    s->cap = cap;
    if (s->v == NULL) {
        die("out of memory");
    }
}

void samples_free(samples_t *s)
{
    free(s->v);
    s->v = NULL;
    s->n = s->cap = 0;
}

void samples_add(samples_t *s, double us)
{
    if (s->n == s->cap) {
        s->cap *= 2;
        s->v = realloc(s->v, s->cap * sizeof(double));
        if (s->v == NULL) {
            die("out of memory");
        }
    }
    s->v[s->n++] = us;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a;
    double y = *(const double *)b;
    return (x > y) - (x < y);
}

void samples_sort(samples_t *s)
{
    qsort(s->v, s->n, sizeof(double), cmp_double);
}

/* Nearest rank. */
double samples_quantile(const samples_t *s, double q)
{
    if (s->n == 0) {
        return 0.0;
    }
    size_t rank = (size_t)(q * (double)s->n + 0.999999);
    if (rank < 1) {
        rank = 1;
    }
    return s->v[(rank > s->n ? s->n : rank) - 1];
}

double samples_max(const samples_t *s)
{
    return s->n > 0 ? s->v[s->n - 1] : 0.0;
}

int epoll_for_two(int fd_a, int fd_b, const char *who)
{
    int epoll_fd = epoll_create1(EPOLL_CLOEXEC);
    struct epoll_event ev_a = {.events = EPOLLIN, .data.fd = fd_a};
    struct epoll_event ev_b = {.events = EPOLLIN, .data.fd = fd_b};
    if (epoll_fd < 0 || epoll_ctl(epoll_fd, EPOLL_CTL_ADD, fd_a, &ev_a) != 0 ||
        epoll_ctl(epoll_fd, EPOLL_CTL_ADD, fd_b, &ev_b) != 0) {
        die("%s: cannot set up epoll", who);
    }
    return epoll_fd;
}
