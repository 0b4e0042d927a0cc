/* SPDX-License-Identifier: BSD-3-Clause */
/* --scenario, --config and --record files. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "config_file.h"
#include "gripper.h"
#include "harness.h"

#include "fleet.h"
#include "options.h"
#include "record.h"
#include "settings_table.h"
#include "simctl/scenario.h"
#include "sim/sim_models.h"
#include "wsg/wsg_types.h"

static bool load_scenario(void *path)
{
    return scenario_load(simctl_scenario(t_sim), path, 0);
}

START_TEST(scenario_runs_on_the_simulated_clock)
{
    const char *path = t_temp_file("# a part slips out 500 ms into the hold\n"
                                   "100 PART(40, 100)\n"
                                   "\n"
                                   "+1400 PART_SLIP()\n"
                                   "2000 FAULT(\"POWER\")\n");
    uint64_t start = t_now_us();
    ck_assert(scenario_load(simctl_scenario(t_sim), path, start));
    ck_assert_uint_eq(scenario_pending(simctl_scenario(t_sim)), 3);
    ck_assert_uint_eq(scenario_next_us(simctl_scenario(t_sim)), start + 100000u);
    t_step_ms(99);
    ck_assert_str_eq(ctl("PART?"), "PART=[0,0,0,0]");
    t_step_ms(1);
    ck_assert_str_eq(ctl("PART?"), "PART=[1,40,100,0]");
    GCL_EQ("GRIP(40, 40)", "ACK GRIP");
    ck_assert_int_ge(t_until("FIN GRIP", 1000), 0);
    ck_assert_int_eq(t_gripstate(), GS_HOLDING);
    t_step_ms((double)(start + 1500000u - t_now_us()) / 1000.0);
    ck_assert_uint_eq(scenario_pending(simctl_scenario(t_sim)), 1);
    t_step_ms(100);
    ck_assert_int_eq(t_gripstate(), GS_PART_LOST);
    t_step_ms(400);
    ck_assert_uint_eq(scenario_pending(simctl_scenario(t_sim)), 0);
    ck_assert_int_eq(t_flag(SF_POWER_FAULT), 1);
    remove(path);
    scenario_unload(simctl_scenario(t_sim));
}
END_TEST

static void expect_scenario_error(const char *text, const char *message)
{
    const char *path = t_temp_file(text);
    bool ok = true;
    const char *err = t_capture_stderr(load_scenario, (void *)path, &ok);
    ck_assert(!ok);
    char expect[256];
    snprintf(expect, sizeof(expect), "wsgsim: %s:%s", path, message);
    ck_assert_msg(strstr(err, expect) != NULL, "got: %s want: %s", err, expect);
    remove(path);
}

START_TEST(bad_scenario_lines_name_file_and_line)
{
    expect_scenario_error("100 PAUSE()\nsoon PART(40)\n",
                          "2: expected a time in ms (e.g. 1500 or +200): soon");
    expect_scenario_error("100 PAUSE()\n50 RESUME()\n", "2: times must not go backwards: 50");
    expect_scenario_error("# c\n\n100 WARP()\n",
                          "3: unknown control command (HELP? lists them): WARP()");
    expect_scenario_error("100 STEP(5)\n", "1: STEP cannot be used in a scenario: STEP(5)");
    expect_scenario_error("100 PART()\n", "1: not enough arguments; usage: "
                                          "PART(width[,stiffness[,slip_force]]) | PART?: PART()");
}
END_TEST

START_TEST(scenario_arguments_are_checked_at_start)
{
    expect_scenario_error("0 PART(40)\n0 PART(400)\n",
                          "2: ERR PART 28 width must be above 0 and below the 110 mm stroke: "
                          "PART(400)");
    expect_scenario_error("0 FAULT(\"FINGER_POWER\",0.5)\n",
                          "1: ERR FAULT 28 the finger must be an integer 0 to 1: "
                          "FAULT(\"FINGER_POWER\",0.5)");
    expect_scenario_error("0 FAULT(\"MELTDOWN\")\n", "1: ERR FAULT 24 unknown fault MELTDOWN");
    expect_scenario_error("0 DELAY(10,0.5)\n", "1: ERR DELAY 28 the session id must be");
    expect_scenario_error("0 AMBIENT=900\n", "1: ERR AMBIENT 28 ambient must be -40 to 150 C");
    expect_scenario_error("0 SCALE=0\n", "1: ERR SCALE 28 the scale must be");
    expect_scenario_error("0 FAILNEXT(\"MOVE\",99)\n", "1: ERR FAILNEXT 28 the code must be");
    expect_scenario_error("0 CLEAR(\"FAILNEXT\",1)\n", "1: ERR CLEAR 12 FAILNEXT takes no finger");
    expect_scenario_error("0 LOG(12)\n", "1: ERR LOG 24 argument 1 must be a name");
    /* checking changes nothing; what depends on the state is left to run time */
    const char *path = t_temp_file("0 PART(40)\n0 FAULT(POWER)\n0 SCALE=2\n0 AMBIENT=30\n"
                                   "0 DELAY(10,99)\n0 CUT(98)\n0 PART_REMOVE()\n"
                                   "0 OBSTACLE(30)\n0 FAILNEXT(MOVE,18)\n0 LOG(hello)\n");
    ck_assert(scenario_load(simctl_scenario(t_sim), path, t_now_us() + 1000u));
    ck_assert_str_eq(ctl("PART?"), "PART=[0,0,0,0]");
    ck_assert_str_eq(ctl("OBSTACLE?"), "OBSTACLE=[0,0]");
    ck_assert_str_eq(ctl("FAULTS?"), "FAULTS=[]");
    ck_assert_str_eq(ctl("SCALE?"), "SCALE=1");
    ck_assert_str_eq(ctl("AMBIENT?"), "AMBIENT=25");
    remove(path);
    scenario_unload(simctl_scenario(t_sim));
}
END_TEST

/* The configuration the tests read files into themselves (options_parse()
 * makes one only for --config or --save-file): one for the process, given
 * to opts. */
static config_file_t *config_of(host_options_t *opts)
{
    static config_file_t *shared;
    if (shared == NULL) {
        shared = config_file_create();
        ck_assert_ptr_nonnull(shared);
    }
    opts->config = shared;
    return shared;
}

typedef struct {
    const char *path;
    host_options_t *opts;
} config_args_t;

static bool load_config(void *arg)
{
    config_args_t *a = arg;
    return config_file_load(config_of(a->opts), a->path, NULL, a->opts) &&
           config_file_check(a->opts->config, a->opts->model);
}

static const char *config_error(const char *text, bool *ok)
{
    static char *argv[] = {"wsgsim", NULL};
    static host_options_t opts;
    options_parse(1, argv, &opts);
    config_args_t a = {t_temp_file(text), &opts};
    static char out[512];
    snprintf(out, sizeof(out), "%s", t_capture_stderr(load_config, &a, ok));
    char *at = strstr(out, a.path);
    remove(a.path);
    return at != NULL ? at + strlen(a.path) : out;
}

START_TEST(config_sets_the_device_like_its_web_interface)
{
    static char *argv[] = {"wsgsim", NULL};
    host_options_t opts;
    options_parse(1, argv, &opts);
    const char *path = t_temp_file("; web interface settings\n"
                                   "[device]\nmodel = WSG 32-068\nserial = 4711\n"
                                   "tag = \"cell 3\"\nfirmware_version = 4.1.2\n"
                                   "hardware_revision = 7\n"
                                   "[motion]\ndefault_force = 20\ndefault_speed = 50\n"
                                   "default_acceleration = 800\ndefault_pullback = 5\n"
                                   "part_width_tolerance = 3\nclamping_travel = 4\n"
                                   "soft_limits = yes\nsoft_limit_minus = 2\n"
                                   "soft_limit_plus = 60\nhoming_direction = negative\n"
                                   "[network]\ntcp_port = 1500\nudp_port = 1501\n"
                                   "max_clients = 3\ndisconnect_faststop = no\n"
                                   "sim_port = 7000\nsim_bind = ::1\n");
    ck_assert(config_file_load(config_of(&opts), path, NULL, &opts));
    ck_assert(config_file_check(opts.config, opts.model));
    ck_assert_int_eq(opts.tcp_port, 1500);
    ck_assert_int_eq(opts.udp_port, 1501);
    ck_assert_int_eq(opts.max_clients, 3);
    ck_assert(!opts.disconnect_faststop);
    ck_assert_int_eq(opts.sim_port, 7000);
    ck_assert_str_eq(opts.sim_bind, "::1");
    t_reinit(&opts);
    const wsg_config_t *cfg = wsg_device_snapshot(&fleet_gripper(t_fleet, 0)->device)->config;
    ck_assert_str_eq(cfg->devtype, "WSG 32-068");
    ck_assert_uint_eq(cfg->serial, 4711);
    ck_assert_str_eq(cfg->tag, "cell 3");
    ck_assert_str_eq(cfg->version, "4.1.2");
    ck_assert_uint_eq(cfg->hw_revision, 7);
    ck_assert_float_eq(cfg->default_force_n, 20.0f);
    ck_assert_float_eq(cfg->default_clt_mm, 4.0f);
    ck_assert(cfg->soft_limits_enabled);
    ck_assert(!cfg->home_positive);
    ck_assert(!cfg->disconnect_raises_faststop);
    /* and the device answers with it */
    t_reopen();
    GCL_EQ("TAG?", "TAG=\"cell 3\"");
    GCL_EQ("SN?", "SN=4711");
    GCL_EQ("CLT?", "CLT=4.0");
    remove(path);
}
END_TEST

/* [mechanics]: the gripper's own figures reach the device and its world;
 * times in ms in the file, us in the configuration. */
START_TEST(config_sets_the_mechanics)
{
    static char *argv[] = {"wsgsim", NULL};
    host_options_t opts;
    options_parse(1, argv, &opts);
    const char *path = t_temp_file("[mechanics]\nspeed_limit = 380\nacceleration_scale = 0.8\n"
                                   "homing_speed = 40\nstop_deceleration = 3000\n"
                                   "fast_stop_deceleration = 7000\nforce_rise = 600\n"
                                   "settle_time = 15\nblock_detect_time = 30\n"
                                   "home_block_detect_time = 80\npart_lost_time = 0.001\n");
    ck_assert(config_file_load(config_of(&opts), path, NULL, &opts));
    ck_assert(config_file_check(opts.config, opts.model));
    t_reinit(&opts);
    gripper_t *g = fleet_gripper(t_fleet, 0);
    const wsg_config_t *cfg = wsg_device_snapshot(&g->device)->config;
    const wsg_mechanics_t *m = &cfg->mechanics;
    ck_assert_float_eq(m->speed_limit_mm_s, 380.0f);
    ck_assert_float_eq(m->accel_scale, 0.8f);
    ck_assert_float_eq(cfg->homing_speed_mm_s, 40.0f);
    ck_assert_uint_eq(m->settle_us, 15000u);
    ck_assert_uint_eq(m->block_detect_us, 30000u);
    ck_assert_uint_eq(m->home_block_detect_us, 80000u);
    ck_assert_uint_eq(m->part_lost_us, 1u);
    ck_assert_float_eq(g->world.axis.drive.force_rise_n_s, 600.0f);
    ck_assert_float_eq(g->world.axis.drive.stop_decel_mm_s2, 3000.0f);
    ck_assert_float_eq(g->world.axis.emergency_accel_mm_s2, 7000.0f);
    remove(path);
}
END_TEST

START_TEST(bad_config_lines_name_file_and_line)
{
    bool ok = true;
    ck_assert_str_eq(config_error("[motion]\ndefault_force = 20\ncolour = red\n", &ok),
                     ":3: [motion] colour: unknown key (every key: " WSGSIM_EXAMPLE_CONFIG ")\n");
    ck_assert(!ok);
    ck_assert_str_eq(config_error("[motion]\n\ndefault_speed = fast\n", &ok),
                     ":3: [motion] default_speed: expected a number\n");
    ck_assert_str_eq(config_error("[gripper]\nspeed = 1\n", &ok),
                     ":2: [gripper] speed: unknown key (every key: " WSGSIM_EXAMPLE_CONFIG ")\n");
    ck_assert_str_eq(config_error("[motion]\ndefault_force = 500\n", &ok),
                     ":2: [motion] default_force: 500 is outside 5..80 for this model\n");
    ck_assert_str_eq(config_error("[network]\nsim_bind = 0.0.0.0\n", &ok),
                     ":2: [network] sim_bind: the control port may only be bound to a loopback "
                     "address here; use --sim-bind on the command line to expose it\n");
    ck_assert_str_eq(config_error("[motion]\nsoft_limit_minus = 50\nsoft_limit_plus = 20\n", &ok),
                     ":3: [motion] soft_limit_plus: soft_limit_minus must be below "
                     "soft_limit_plus\n");
    ck_assert_str_eq(config_error("[device]\nmodel = WSG 99\n", &ok),
                     ":2: [device] model: unknown model (see wsgsim --list-models)\n");
    ck_assert_str_eq(config_error("[mechanics]\nacceleration_scale = 0\n", &ok),
                     ":2: [mechanics] acceleration_scale: 0 is outside 0.1..10\n");
    ck_assert_str_eq(config_error("[mechanics]\nsettle_time = soon\n", &ok),
                     ":2: [mechanics] settle_time: expected a number\n");
    ck_assert_str_eq(config_error("[device\n", &ok),
                     ":1: not a section header or key = value line\n");
    ck_assert(!ok);
}
END_TEST

/* Found by fuzzing (tests/fuzz/fuzz_config.c): libinih reads an indented
 * line as the continuation of the key before it, so " 25-064" after
 * "tag = three" made the tag "25-064", and a Save that wrote the tag left
 * the line to change it again at the next start. Indentation means nothing:
 * an indented line is a line of its own. */
START_TEST(an_indented_config_line_continues_nothing)
{
    static char *argv[] = {"wsgsim", NULL};
    host_options_t opts;
    options_parse(1, argv, &opts);
    const char *path = t_temp_file("[device]\ntag = three\n  serial = 99\n");
    ck_assert(config_file_load(config_of(&opts), path, NULL, &opts));
    ck_assert(config_file_check(opts.config, opts.model));
    wsg_config_t cfg;
    wsg_sim_model_config(wsg_sim_model_default(), &cfg);
    config_file_apply(opts.config, &cfg);
    ck_assert_str_eq(cfg.tag, "three");
    ck_assert_uint_eq(cfg.serial, 99);
    remove(path);
    bool ok = true;
    ck_assert_str_eq(config_error("[device]\ntag = three\n 25-064\n", &ok),
                     ":3: not a section header or key = value line\n");
    ck_assert(!ok);
}
END_TEST

/* Found by fuzzing: libinih skips any blank before a line (CR, form feed,
 * ...), the Save only spaces and tabs, so "\r[device.1]" was a section for
 * the one and text for the other, which then saved keys into the wrong
 * section. A section or key line holds no CR, vertical tab or form feed. */
START_TEST(a_control_character_in_a_config_line_is_refused)
{
    bool ok = true;
    ck_assert_str_eq(config_error("[device]\n\r[device.1]\ntag = x\n", &ok),
                     ":2: control character 0x0d at column 1 (a section or key line holds no "
                     "CR, vertical tab or form feed)\n");
    ck_assert(!ok);
    ck_assert_str_eq(config_error("[device]\ntag = x\fy\n", &ok),
                     ":2: control character 0x0c at column 8 (a section or key line holds no "
                     "CR, vertical tab or form feed)\n");
    ck_assert_str_eq(config_error("; a comment holds anything \x01\r\n[device]\n\ttag = x\n", &ok),
                     "");
    ck_assert(ok);
}
END_TEST

typedef struct {
    const char *config;
    const char *saved;
    host_options_t *opts;
} layered_args_t;

static bool load_layered(void *arg)
{
    layered_args_t *a = arg;
    return config_file_load(config_of(a->opts), a->config, a->saved, a->opts) &&
           config_file_check(a->opts->config, a->opts->model);
}

/* --save-file: read after --config, its keys win; missing is nothing saved;
 * its errors name it, also those found after loading (the range check). */
START_TEST(save_file_is_read_over_the_config)
{
    static char *argv[] = {"wsgsim", NULL};
    host_options_t opts;
    options_parse(1, argv, &opts);
    char config[256];
    snprintf(config, sizeof(config), "%s",
             t_temp_file("[device]\ntag = \"cell\"\n[motion]\ndefault_force = 20\n"
                         "default_speed = 50\n[network]\ntcp_port = 1500\n"));
    const char *saved = t_temp_file("# saved\n[motion]\ndefault_force = 33\n"
                                    "[device]\ntag = \"saved\"\n");
    layered_args_t a = {config, saved, &opts};
    bool ok = false;
    t_capture_stderr(load_layered, &a, &ok);
    ck_assert(ok);
    ck_assert_int_eq(opts.tcp_port, 1500);
    t_reinit(&opts);
    const wsg_config_t *cfg = wsg_device_snapshot(&fleet_gripper(t_fleet, 0)->device)->config;
    ck_assert_float_eq(cfg->default_force_n, 33.0f);
    ck_assert_float_eq(cfg->default_speed_mm_s, 50.0f);
    ck_assert_str_eq(cfg->tag, "saved");
    remove(saved);
    t_capture_stderr(load_layered, &a, &ok); /* nothing saved yet */
    ck_assert(ok);
    saved = t_temp_file("[motion]\n\ndefault_force = 500\n");
    a.saved = saved;
    char expect[512];
    snprintf(expect, sizeof(expect),
             "wsgsim: %s:3: [motion] default_force: 500 is outside 5..80 for this model\n", saved);
    ck_assert_str_eq(t_capture_stderr(load_layered, &a, &ok), expect);
    ck_assert(!ok);
    remove(saved);
    saved = t_temp_file("[motion]\ncolour = red\n");
    a.saved = saved;
    snprintf(expect, sizeof(expect),
             "wsgsim: %s:2: [motion] colour: unknown key (every key: " WSGSIM_EXAMPLE_CONFIG ")\n",
             saved);
    ck_assert_str_eq(t_capture_stderr(load_layered, &a, &ok), expect);
    ck_assert(!ok);
    remove(saved);
    remove(config);
}
END_TEST

/* Given twice, --config and --save-file count as every other option: the
 * last one. */
START_TEST(last_config_and_save_file_count)
{
    char first[64], second[64];
    snprintf(first, sizeof(first), "%s", t_temp_file("[motion]\ndefault_force = 20\n"));
    snprintf(second, sizeof(second), "%s", t_temp_file("[motion]\ndefault_force = 30\n"));
    char *argv[] = {"wsgsim",   "--config", first,         "--save-file=/nowhere/a.ini",
                    "--config", second,     "--save-file", "/nowhere/b.ini",
                    NULL};
    host_options_t opts;
    ck_assert_int_eq(options_parse(8, argv, &opts), OPTIONS_RUN);
    ck_assert_str_eq(opts.config_path, second);
    ck_assert_str_eq(opts.save_path, "/nowhere/b.ini");
    t_reinit(&opts);
    ck_assert_float_eq(
        wsg_device_snapshot(&fleet_gripper(t_fleet, 0)->device)->config->default_force_n, 30.0f);
    remove(first);
    remove(second);
    options_release(&opts);
}
END_TEST

/* A 199-character comment whose tail libinih's 200-byte line buffer used to
 * cut off and parse as a key line. */
static char *long_comment_then(const char *after)
{
    static char text[1024];
    char comment[200];
    memset(comment, 'x', sizeof(comment));
    comment[0] = '#';
    snprintf(text, sizeof(text), "[device]\n%.*sserial = 999\n%s", (int)sizeof(comment) - 1,
             comment, after);
    return text;
}

START_TEST(config_lines_are_read_whole_or_refused)
{
    static char *argv[] = {"wsgsim", NULL};
    host_options_t opts;
    options_parse(1, argv, &opts);
    const char *path = t_temp_file(long_comment_then("tag = long comments\n"));
    ck_assert(config_file_load(config_of(&opts), path, NULL, &opts));
    ck_assert(config_file_check(opts.config, opts.model));
    remove(path);
    t_reinit(&opts);
    t_reopen();
    GCL_EQ("SN?", "SN=12345678"); /* the comment set nothing */
    GCL_EQ("TAG?", "TAG=\"long comments\"");
    bool ok = true;
    /* line numbers after a long line stay right */
    ck_assert_str_eq(config_error(long_comment_then("colour = red\n"), &ok),
                     ":3: [device] colour: unknown key (every key: " WSGSIM_EXAMPLE_CONFIG ")\n");
    char key_line[400];
    snprintf(key_line, sizeof(key_line), "[device]\ntag = %0300d\n", 7);
    ck_assert_ptr_nonnull(strstr(config_error(key_line, &ok),
                                 ":2: line too long for a section or key line (at most "));
    ck_assert(!ok);
    ck_assert_str_eq(config_error("[device]\ntag = a\001b\n", &ok),
                     ":2: [device] tag: expected printable text without '\"', at most 47 "
                     "characters\n");
}
END_TEST

static bool load_config_path(void *path)
{
    static char *argv[] = {"wsgsim", NULL};
    host_options_t opts;
    options_parse(1, argv, &opts);
    return config_file_load(config_of(&opts), path, NULL, &opts);
}

/* What loading `path` as a config and as a scenario prints (both must fail). */
static void expect_both_refuse(const char *path, const char *message)
{
    bool ok = true;
    char expect[256];
    snprintf(expect, sizeof(expect), message, path);
    const char *err = t_capture_stderr(load_config_path, (void *)path, &ok);
    ck_assert(!ok);
    ck_assert_msg(strstr(err, expect) != NULL, "config: got %s want %s", err, expect);
    err = t_capture_stderr(load_scenario, (void *)path, &ok);
    ck_assert(!ok);
    ck_assert_msg(strstr(err, expect) != NULL, "scenario: got %s want %s", err, expect);
}

START_TEST(unreadable_files_are_refused_clearly)
{
    char dir[] = "/tmp/simctl_dir_XXXXXX";
    ck_assert_ptr_nonnull(mkdtemp(dir));
    char message[160];
    snprintf(message, sizeof(message), "file %%s: it is a directory");
    expect_both_refuse(dir, message);
    rmdir(dir);
    expect_both_refuse("/dev/zero", "wsgsim: %s:1: NUL byte at column 1");
    char path[] = "/tmp/simctl_nul_XXXXXX";
    int fd = mkstemp(path);
    ck_assert_int_eq(write(fd, "# ok\n0 LOG(a\0b)\n", 17), 17);
    close(fd);
    expect_both_refuse(path, "wsgsim: %s:2: NUL byte at column 8");
    remove(path);
}
END_TEST

START_TEST(scenario_lines_take_trailing_comments)
{
    const char *path = t_temp_file("0 PART(40, 100)   # a part\n"
                                   "+10 LOG(\"# not a comment\") # but this is\n"
                                   "20\tOBSTACLE(60)#tight\n");
    ck_assert(scenario_load(simctl_scenario(t_sim), path, t_now_us()));
    remove(path);
    ck_assert_uint_eq(scenario_pending(simctl_scenario(t_sim)), 3);
    t_step_ms(20);
    ck_assert_uint_eq(scenario_pending(simctl_scenario(t_sim)), 0);
    ck_assert_str_eq(ctl("PART?"), "PART=[1,40,100,0]");
    ck_assert_str_eq(ctl("OBSTACLE?"), "OBSTACLE=[1,60]");
    scenario_unload(simctl_scenario(t_sim));
    char *text = malloc(5000);
    memset(text, ' ', 4999);
    memcpy(text, "0 PART(40)", 10);
    text[4998] = '\n';
    text[4999] = '\0';
    expect_scenario_error(text, "1: line too long (more than 4096 characters)");
    free(text);
}
END_TEST

START_TEST(record_writes_every_line_with_both_clocks)
{
    char path[] = "/tmp/simctl_record_XXXXXX";
    int fd = mkstemp(path);
    ck_assert_int_ge(fd, 0);
    record_t *record = record_open(path, 1);
    ck_assert_ptr_nonnull(record);
    record_attach(record, &fleet_gripper(t_fleet, 0)->device, 0);
    t_step_ms(5);
    GCL_EQ("POS?", "POS=110.0");
    record_control(record, "ctl1", '<', "PAUSE()", 7);
    record_detach(record, &fleet_gripper(t_fleet, 0)->device, 0);
    record_close(record);
    FILE *f = fdopen(fd, "r");
    char lines[5][160] = {{0}};
    for (int i = 0; i < 5 && fgets(lines[i], sizeof(lines[i]), f) != NULL; i++) {
    }
    fclose(f);
    remove(path);
    ck_assert_str_eq(lines[0], "# wsgsim record 2\n");
    unsigned long long sim_s = 0;
    unsigned long sim_us = 0;
    unsigned long long wall_s = 0;
    char channel[16];
    char dir = 0;
    char text[64];
    ck_assert_int_eq(sscanf(lines[2], "%llu.%6lu %llu.%*6u %15s %c %63[^\n]", &sim_s, &sim_us,
                            &wall_s, channel, &dir, text),
                     6);
    ck_assert_uint_eq(sim_s * 1000000u + sim_us, t_now_us());
    ck_assert_uint_gt(wall_s, 1600000000u);
    ck_assert_str_eq(channel, "s1t");
    ck_assert_int_eq(dir, '>'); /* from the client's side: it sent POS? */
    ck_assert_str_eq(text, "POS?");
    ck_assert_ptr_nonnull(strstr(lines[3], " s1t < POS=110.0\n"));
    ck_assert_ptr_nonnull(strstr(lines[4], " ctl1 > PAUSE()\n"));
}
END_TEST

/* Found by fuzzing (tests/fuzz/fuzz_config.c): a stray CR before a line's
 * end ("; cell 3\r\r\n") was copied as text, so the saved line ended in
 * "\r\n" and the next save wrote it differently again. Save ends every line
 * it writes with "\n" alone. */
static char *read_all(const char *path)
{
    static char text[4096];
    FILE *f = fopen(path, "rb");
    ck_assert_ptr_nonnull(f);
    size_t n = fread(text, 1, sizeof(text) - 1, f);
    fclose(f);
    text[n] = '\0';
    return text;
}

START_TEST(config_save_ends_every_line_with_a_newline_alone)
{
    static char *argv[] = {"wsgsim", NULL};
    host_options_t opts;
    options_parse(1, argv, &opts);
    const char *path = t_temp_file("; cell 3\r\r\n[motion]\r\nclamping_travel = 4\r\n");
    ck_assert(config_file_load(config_of(&opts), path, NULL, &opts));
    ck_assert(config_file_check(opts.config, opts.model));
    const wsg_config_t *cfg = wsg_device_snapshot(&fleet_gripper(t_fleet, 0)->device)->config;
    char why[256];
    ck_assert(config_file_save(opts.config, path, 0, cfg, NULL, why, sizeof(why)));
    char first[4096];
    snprintf(first, sizeof(first), "%s", read_all(path));
    ck_assert_ptr_null(strchr(first, '\r'));
    ck_assert_ptr_nonnull(strstr(first, "; cell 3\n[motion]\n"));
    ck_assert(config_file_save(opts.config, path, 0, cfg, NULL, why, sizeof(why)));
    ck_assert_str_eq(read_all(path), first);
    remove(path);
}
END_TEST

/* Loads text as the configuration file, saves device 0's configuration
 * with the tag "new" over it and loads the saved file again: the file as
 * saved (into saved), and the tag device 0 starts with from it. */
static const char *save_new_tag(const char *text, char *saved, size_t cap)
{
    static char *argv[] = {"wsgsim", NULL};
    static wsg_config_t loaded;
    host_options_t opts;
    options_parse(1, argv, &opts);
    const char *path = t_temp_file(text);
    ck_assert(config_file_load(config_of(&opts), path, NULL, &opts));
    ck_assert(config_file_check(opts.config, opts.model));
    wsg_config_t cfg = *wsg_device_snapshot(&fleet_gripper(t_fleet, 0)->device)->config;
    snprintf(cfg.tag, sizeof(cfg.tag), "new");
    char why[256];
    ck_assert(config_file_save(opts.config, path, 0, &cfg, NULL, why, sizeof(why)));
    snprintf(saved, cap, "%s", read_all(path));
    ck_assert(config_file_load(config_of(&opts), path, NULL, &opts));
    wsg_sim_model_config(wsg_sim_model_default(), &loaded);
    config_file_apply(opts.config, &loaded);
    config_file_apply_device(opts.config, 0, &loaded);
    remove(path);
    return loaded.tag;
}

/* Found by fuzzing: libinih reads "key : value" as a key line too, the
 * Save did not, so a "tag : old" in a later [device] section outlived the
 * saved tag and won at the next start. */
START_TEST(config_save_replaces_colon_keys_too)
{
    char saved[4096];
    const char *tag =
        save_new_tag("[device]\ntag = a\n[motion]\n[device]\ntag : old\n", saved, sizeof(saved));
    ck_assert_ptr_null(strstr(saved, "old"));
    ck_assert_str_eq(tag, "new");
}
END_TEST

/* Found by fuzzing: device 0's tag was saved to [device] even when a
 * [device.0] section gave device 0 its tag, which then won at the next
 * start over the saved one. */
START_TEST(config_save_puts_the_tag_where_it_counts)
{
    char saved[4096];
    const char *tag =
        save_new_tag("[device]\ntag = a\n[device.0]\ntag = zero\n", saved, sizeof(saved));
    ck_assert_ptr_nonnull(strstr(saved, "[device]\ntag = a\n[device.0]\ntag = \"new\"\n"));
    ck_assert_str_eq(tag, "new");
}
END_TEST

/* The settings table names every device setting once: one row each, no
 * key given twice in the file or on the page. */
START_TEST(settings_table_names_every_setting_once)
{
    for (int id = 0; id < WSG_SET_COUNT; id++) {
        const settings_row_t *row = settings_table_row((wsg_setting_t)id);
        ck_assert_ptr_nonnull(row);
        ck_assert_int_eq(row->id, id);
    }
    for (unsigned i = 0; i < SETTINGS_TABLE_COUNT; i++) {
        const settings_row_t *a = &settings_table[i];
        for (unsigned k = i + 1u; k < SETTINGS_TABLE_COUNT; k++) {
            const settings_row_t *b = &settings_table[k];
            ck_assert_int_ne(a->id, b->id);
            ck_assert_str_ne(a->json_key, b->json_key);
            ck_assert(a->ini_key == NULL || b->ini_key == NULL ||
                      strcmp(a->ini_key, b->ini_key) != 0);
        }
    }
}
END_TEST

Suite *files_suite(void)
{
    Suite *s = suite_create("files");
    TCase *tc = tcase_create("files");
    tcase_add_checked_fixture(tc, t_setup_homed, t_teardown);
    tcase_add_test(tc, scenario_runs_on_the_simulated_clock);
    tcase_add_test(tc, bad_scenario_lines_name_file_and_line);
    tcase_add_test(tc, scenario_arguments_are_checked_at_start);
    tcase_add_test(tc, scenario_lines_take_trailing_comments);
    tcase_add_test(tc, config_lines_are_read_whole_or_refused);
    tcase_add_test(tc, unreadable_files_are_refused_clearly);
    tcase_add_test(tc, config_sets_the_device_like_its_web_interface);
    tcase_add_test(tc, bad_config_lines_name_file_and_line);
    tcase_add_test(tc, config_save_ends_every_line_with_a_newline_alone);
    tcase_add_test(tc, an_indented_config_line_continues_nothing);
    tcase_add_test(tc, config_sets_the_mechanics);
    tcase_add_test(tc, a_control_character_in_a_config_line_is_refused);
    tcase_add_test(tc, config_save_replaces_colon_keys_too);
    tcase_add_test(tc, config_save_puts_the_tag_where_it_counts);
    tcase_add_test(tc, settings_table_names_every_setting_once);
    tcase_add_test(tc, save_file_is_read_over_the_config);
    tcase_add_test(tc, last_config_and_save_file_count);
    tcase_add_test(tc, record_writes_every_line_with_both_clocks);
    suite_add_tcase(s, tc);
    return s;
}
