/* SPDX-License-Identifier: BSD-3-Clause */
/* The manual's names of the device's enumerations (wsg_names.h). */
#include "wsg/wsg_names.h"

#include <stddef.h>

static const char *const grip_states[GS_COUNT] = {
    [GS_IDLE] = "IDLE",
    [GS_GRASPING] = "GRASPING",
    [GS_NO_PART] = "NO PART",
    [GS_PART_LOST] = "PART LOST",
    [GS_HOLDING] = "HOLDING",
    [GS_RELEASING] = "RELEASING",
    [GS_POSITIONING] = "POSITIONING",
    [GS_ERROR] = "ERROR",
};

static const char *const sysflags[WSG_SYSFLAG_COUNT] = {
    [SF_REFERENCED] = "SF_REFERENCED",
    [SF_MOVING] = "SF_MOVING",
    [SF_BLOCKED_MINUS] = "SF_BLOCKED_MINUS",
    [SF_BLOCKED_PLUS] = "SF_BLOCKED_PLUS",
    [SF_SOFT_LIMIT_MINUS] = "SF_SOFT_LIMIT_MINUS",
    [SF_SOFT_LIMIT_PLUS] = "SF_SOFT_LIMIT_PLUS",
    [SF_AXIS_STOPPED] = "SF_AXIS_STOPPED",
    [SF_TARGET_POS_REACHED] = "SF_TARGET_POS_REACHED",
    [SF_OVERDRIVE_MODE] = "SF_OVERDRIVE_MODE",
    [SF_FORCECNTL_MODE] = "SF_FORCECNTL_MODE",
    [SF_FAST_STOP] = "SF_FAST_STOP",
    [SF_TEMP_WARNING] = "SF_TEMP_WARNING",
    [SF_TEMP_FAULT] = "SF_TEMP_FAULT",
    [SF_POWER_FAULT] = "SF_POWER_FAULT",
    [SF_CURR_FAULT] = "SF_CURR_FAULT",
    [SF_FINGER_FAULT] = "SF_FINGER_FAULT",
    [SF_CMD_FAILURE] = "SF_CMD_FAILURE",
    [SF_SCRIPT_RUNNING] = "SF_SCRIPT_RUNNING",
    [SF_SCRIPT_FAILURE] = "SF_SCRIPT_FAILURE",
};

static const char *const statuses[WSG_STATUS_COUNT] = {
    [E_SUCCESS] = "E_SUCCESS",
    [E_NOT_AVAILABLE] = "E_NOT_AVAILABLE",
    [E_NO_SENSOR] = "E_NO_SENSOR",
    [E_NOT_INITIALIZED] = "E_NOT_INITIALIZED",
    [E_ALREADY_RUNNING] = "E_ALREADY_RUNNING",
    [E_FEATURE_NOT_SUPPORTED] = "E_FEATURE_NOT_SUPPORTED",
    [E_INCONSISTENT_DATA] = "E_INCONSISTENT_DATA",
    [E_TIMEOUT] = "E_TIMEOUT",
    [E_READ_ERROR] = "E_READ_ERROR",
    [E_WRITE_ERROR] = "E_WRITE_ERROR",
    [E_INSUFFICIENT_RESOURCES] = "E_INSUFFICIENT_RESOURCES",
    [E_CHECKSUM_ERROR] = "E_CHECKSUM_ERROR",
    [E_NO_PARAM_EXPECTED] = "E_NO_PARAM_EXPECTED",
    [E_NOT_ENOUGH_PARAMS] = "E_NOT_ENOUGH_PARAMS",
    [E_CMD_UNKNOWN] = "E_CMD_UNKNOWN",
    [E_CMD_FORMAT_ERROR] = "E_CMD_FORMAT_ERROR",
    [E_ACCESS_DENIED] = "E_ACCESS_DENIED",
    [E_ALREADY_OPEN] = "E_ALREADY_OPEN",
    [E_CMD_FAILED] = "E_CMD_FAILED",
    [E_CMD_ABORTED] = "E_CMD_ABORTED",
    [E_INVALID_HANDLE] = "E_INVALID_HANDLE",
    [E_NOT_FOUND] = "E_NOT_FOUND",
    [E_NOT_OPEN] = "E_NOT_OPEN",
    [E_IO_ERROR] = "E_IO_ERROR",
    [E_INVALID_PARAMETER] = "E_INVALID_PARAMETER",
    [E_INDEX_OUT_OF_BOUNDS] = "E_INDEX_OUT_OF_BOUNDS",
    [E_CMD_PENDING] = "E_CMD_PENDING",
    [E_OVERRUN] = "E_OVERRUN",
    [E_RANGE_ERROR] = "E_RANGE_ERROR",
    [E_AXIS_BLOCKED] = "E_AXIS_BLOCKED",
    [E_FILE_EXISTS] = "E_FILE_EXISTS",
};

const char *wsg_grip_state_name(wsg_grip_state_t state)
{
    return (unsigned)state < GS_COUNT ? grip_states[state] : "?";
}

const char *wsg_sysflag_name(unsigned bit)
{
    return bit < WSG_SYSFLAG_COUNT ? sysflags[bit] : NULL;
}

const char *wsg_status_name(wsg_status_t status)
{
    return (unsigned)status < WSG_STATUS_COUNT ? statuses[status] : "?";
}
