/* SPDX-License-Identifier: BSD-3-Clause */
#include "wsg/wsg_status.h"

static const char *const descriptions[WSG_STATUS_COUNT] = {
    [E_SUCCESS] = "No error occurred, operation was successful",
    [E_NOT_AVAILABLE] = "Function or data is not available",
    [E_NO_SENSOR] = "No measurement converter is connected",
    [E_NOT_INITIALIZED] = "Device was not initialized",
    [E_ALREADY_RUNNING] = "The data acquisition is already running",
    [E_FEATURE_NOT_SUPPORTED] = "The requested feature is currently not available",
    [E_INCONSISTENT_DATA] = "One or more parameters are inconsistent",
    [E_TIMEOUT] = "Timeout error",
    [E_READ_ERROR] = "Error while reading data",
    [E_WRITE_ERROR] = "Error while writing data",
    [E_INSUFFICIENT_RESOURCES] = "No more memory available",
    [E_CHECKSUM_ERROR] = "Checksum error",
    [E_NO_PARAM_EXPECTED] = "A Parameter was given, but none expected",
    [E_NOT_ENOUGH_PARAMS] = "Not enough parameters to execute the command",
    [E_CMD_UNKNOWN] = "Unknown command",
    [E_CMD_FORMAT_ERROR] = "Command format error",
    [E_ACCESS_DENIED] = "Access denied",
    [E_ALREADY_OPEN] = "Interface is already open",
    [E_CMD_FAILED] = "Error while executing a command",
    [E_CMD_ABORTED] = "Command execution was aborted by the user",
    [E_INVALID_HANDLE] = "Invalid handle",
    [E_NOT_FOUND] = "Device or file not found",
    [E_NOT_OPEN] = "Device or file not open",
    [E_IO_ERROR] = "Input/Output Error",
    [E_INVALID_PARAMETER] = "Wrong parameter",
    [E_INDEX_OUT_OF_BOUNDS] = "Index out of bounds",
    [E_CMD_PENDING] = "No error, but the command was not completed, yet. Another return "
                      "message will follow including an error code, if the function was "
                      "completed.",
    [E_OVERRUN] = "Data overrun",
    [E_RANGE_ERROR] = "Range error",
    [E_AXIS_BLOCKED] = "Axis blocked",
    [E_FILE_EXISTS] = "File already exists",
};

const char *wsg_status_description(wsg_status_t status)
{
    if ((unsigned)status >= WSG_STATUS_COUNT) {
        return "Unknown error";
    }
    return descriptions[status];
}
