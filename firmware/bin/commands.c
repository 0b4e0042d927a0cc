/* SPDX-License-Identifier: BSD-3-Clause */
/* The binary protocol's command table: each built-in command's ID, its name
 * (as tools/wsgbin names it) and its handler. */
#include "bin/bin_internal.h"

static const bin_command_t commands[] = {
    {0x06, "loop", wsg_bin_loop},
    {0x07, "disconnect", wsg_bin_disconnect},
    {0x20, "homing", wsg_bin_homing},
    {0x21, "preposition", wsg_bin_preposition},
    {0x22, "stop", wsg_bin_stop},
    {0x23, "fast-stop", wsg_bin_fast_stop},
    {0x24, "ack", wsg_bin_ack},
    {0x25, "grasp", wsg_bin_grasp},
    {0x26, "release", wsg_bin_release},
    {0x30, "set-acc", wsg_bin_set_acc},
    {0x31, "get-acc", wsg_bin_get_acc},
    {0x32, "set-force", wsg_bin_set_force},
    {0x33, "get-force-limit", wsg_bin_get_force_limit},
    {0x34, "set-soft-limits", wsg_bin_set_soft_limits},
    {0x35, "get-soft-limits", wsg_bin_get_soft_limits},
    {0x36, "clear-soft-limits", wsg_bin_clear_soft_limits},
    {0x37, "overdrive", wsg_bin_overdrive},
    {0x38, "tare", wsg_bin_tare},
    {0x40, "get-state", wsg_bin_get_state},
    {0x41, "get-grasp-state", wsg_bin_get_grasp_state},
    {0x42, "get-stats", wsg_bin_get_stats},
    {0x43, "get-width", wsg_bin_get_width},
    {0x44, "get-speed", wsg_bin_get_speed},
    {0x45, "get-force", wsg_bin_get_force},
    {0x46, "get-temp", wsg_bin_get_temp},
    {0x50, "system-info", wsg_bin_system_info},
    {0x51, "set-tag", wsg_bin_set_tag},
    {0x52, "get-tag", wsg_bin_get_tag},
    {0x53, "get-limits", wsg_bin_get_limits},
    {0x60, "finger1-info", wsg_bin_finger_info},
    {0x61, "finger1-flags", wsg_bin_finger_flags},
    {0x62, "finger1-power", wsg_bin_finger_power},
    {0x63, "finger1-data", wsg_bin_finger_data},
    {0x70, "finger2-info", wsg_bin_finger_info},
    {0x71, "finger2-flags", wsg_bin_finger_flags},
    {0x72, "finger2-power", wsg_bin_finger_power},
    {0x73, "finger2-data", wsg_bin_finger_data},
};

const bin_command_t *wsg_bin_find_command(uint8_t id)
{
    for (size_t i = 0; i < sizeof(commands) / sizeof(commands[0]); i++) {
        if (commands[i].id == id) {
            return &commands[i];
        }
    }
    return NULL;
}

const char *wsg_bin_command_name(uint8_t id)
{
    const bin_command_t *cmd = wsg_bin_find_command(id);
    return cmd != NULL ? cmd->name : NULL;
}
