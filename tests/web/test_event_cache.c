/* SPDX-License-Identifier: BSD-3-Clause */
/* Check tests of the event streams' text cache (host/web/web_event_cache.c):
 * one build per device and tick, kept for the tick's other streams after
 * the first has sent it, freed once unused and past, none left behind. */
#include <check.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "web/web_event_cache.h"

/* Two devices' states, as the builder writes them. */
static const char device_a[] = "a", device_b[] = "b";

static web_event_cache_t cache;
static unsigned builds;
static bool out_of_memory;

/* "DEVICE ID BUILD", a build counter making every build's text unique. */
static char *build(void *ctx, uint64_t id, size_t *len)
{
    if (out_of_memory) {
        return NULL;
    }
    char *text = malloc(64);
    ck_assert_ptr_nonnull(text);
    builds++;
    *len =
        (size_t)snprintf(text, 64, "%s %llu %u", (const char *)ctx, (unsigned long long)id, builds);
    return text;
}

static web_event_t *take(const char *device, uint64_t fire, uint64_t id)
{
    return web_event_cache_take(&cache, device, fire, id, build, (void *)device);
}

static unsigned cached(void)
{
    unsigned n = 0;
    LIST_EACH (node, &cache.events) {
        n++;
    }
    return n;
}

static void setup(void)
{
    memset(&cache, 0, sizeof(cache));
    builds = 0;
    out_of_memory = false;
}

static void teardown(void)
{
    web_event_cache_drop_unused(&cache);
    ck_assert(list_empty(&cache.events));
}

START_TEST(the_streams_of_a_tick_share_one_build_sent_one_after_the_other)
{
    web_event_t *first = take(device_a, 5, 1);
    ck_assert_ptr_nonnull(first);
    ck_assert_str_eq(first->text, "a 1 1");
    web_event_cache_release(&cache, first, 5); /* sent whole before the next asks */
    web_event_t *second = take(device_a, 5, 1);
    ck_assert_ptr_nonnull(second);
    ck_assert_str_eq(second->text, "a 1 1");
    ck_assert_uint_eq(builds, 1);
    web_event_cache_release(&cache, second, 5);
}
END_TEST

START_TEST(another_tick_device_or_id_is_built_anew)
{
    web_event_t *e[4] = {take(device_a, 5, 1), take(device_a, 6, 1), take(device_b, 6, 1),
                         take(device_a, 6, 2)};
    ck_assert_uint_eq(builds, 4);
    ck_assert_str_eq(e[1]->text, "a 1 2");
    ck_assert_str_eq(e[2]->text, "b 1 3");
    ck_assert_str_eq(e[3]->text, "a 2 4");
    for (int i = 0; i < 4; i++) {
        web_event_cache_release(&cache, e[i], 6);
    }
}
END_TEST

START_TEST(an_unused_event_goes_when_a_later_tick_builds)
{
    web_event_cache_release(&cache, take(device_a, 5, 1), 5);
    ck_assert_uint_eq(cached(), 1);
    web_event_t *later = take(device_a, 6, 1);
    ck_assert_uint_eq(cached(), 1);
    ck_assert_ptr_eq(LIST_ITEM(cache.events.first, web_event_t, link), later);
    web_event_cache_release(&cache, later, 6);
}
END_TEST

START_TEST(an_event_being_sent_stays_past_its_tick_until_its_last_user)
{
    web_event_t *slow = take(device_a, 5, 1);
    web_event_t *also = take(device_a, 5, 1);
    web_event_t *later = take(device_a, 6, 1);
    ck_assert_uint_eq(cached(), 2);
    ck_assert_str_eq(slow->text, "a 1 1");
    web_event_cache_release(&cache, slow, 6);
    ck_assert_uint_eq(cached(), 2);
    web_event_cache_release(&cache, also, 6); /* its last user, its tick past */
    ck_assert_uint_eq(cached(), 1);
    ck_assert_ptr_eq(LIST_ITEM(cache.events.first, web_event_t, link), later);
    web_event_cache_release(&cache, later, 6);
}
END_TEST

START_TEST(out_of_memory_leaves_the_cache_as_it_was)
{
    web_event_t *held = take(device_a, 5, 1);
    out_of_memory = true;
    ck_assert_ptr_null(take(device_b, 5, 1));
    ck_assert_uint_eq(cached(), 1);
    ck_assert_uint_eq(held->users, 1);
    web_event_cache_release(&cache, held, 5);
}
END_TEST

START_TEST(dropping_the_unused_keeps_what_is_being_sent)
{
    web_event_t *held = take(device_a, 5, 1);
    web_event_cache_release(&cache, take(device_b, 5, 1), 5);
    web_event_cache_drop_unused(&cache);
    ck_assert_uint_eq(cached(), 1);
    ck_assert_ptr_eq(LIST_ITEM(cache.events.first, web_event_t, link), held);
    web_event_cache_release(&cache, held, 5);
}
END_TEST

int main(void)
{
    Suite *s = suite_create("web_event_cache");
    TCase *tc = tcase_create("event_cache");
    tcase_add_checked_fixture(tc, setup, teardown);
    tcase_add_test(tc, the_streams_of_a_tick_share_one_build_sent_one_after_the_other);
    tcase_add_test(tc, another_tick_device_or_id_is_built_anew);
    tcase_add_test(tc, an_unused_event_goes_when_a_later_tick_builds);
    tcase_add_test(tc, an_event_being_sent_stays_past_its_tick_until_its_last_user);
    tcase_add_test(tc, out_of_memory_leaves_the_cache_as_it_was);
    tcase_add_test(tc, dropping_the_unused_keeps_what_is_being_sent);
    suite_add_tcase(s, tc);
    SRunner *runner = srunner_create(s);
    srunner_run_all(runner, CK_NORMAL);
    int failed = srunner_ntests_failed(runner);
    srunner_free(runner);
    return failed == 0 ? EXIT_SUCCESS : EXIT_FAILURE;
}
