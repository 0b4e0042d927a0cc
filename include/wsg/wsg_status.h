/* SPDX-License-Identifier: BSD-3-Clause */
/* Status codes of Appendix A. */
#ifndef WSG_STATUS_H
#define WSG_STATUS_H

typedef enum {
    E_SUCCESS = 0,
    E_NOT_AVAILABLE = 1,
    E_NO_SENSOR = 2,
    E_NOT_INITIALIZED = 3,
    E_ALREADY_RUNNING = 4,
    E_FEATURE_NOT_SUPPORTED = 5,
    E_INCONSISTENT_DATA = 6,
    E_TIMEOUT = 7,
    E_READ_ERROR = 8,
    E_WRITE_ERROR = 9,
    E_INSUFFICIENT_RESOURCES = 10,
    E_CHECKSUM_ERROR = 11,
    E_NO_PARAM_EXPECTED = 12,
    E_NOT_ENOUGH_PARAMS = 13,
    E_CMD_UNKNOWN = 14,
    E_CMD_FORMAT_ERROR = 15,
    E_ACCESS_DENIED = 16,
    E_ALREADY_OPEN = 17,
    E_CMD_FAILED = 18,
    E_CMD_ABORTED = 19,
    E_INVALID_HANDLE = 20,
    E_NOT_FOUND = 21,
    E_NOT_OPEN = 22,
    E_IO_ERROR = 23,
    E_INVALID_PARAMETER = 24,
    E_INDEX_OUT_OF_BOUNDS = 25,
    E_CMD_PENDING = 26,
    E_OVERRUN = 27,
    E_RANGE_ERROR = 28,
    E_AXIS_BLOCKED = 29,
    E_FILE_EXISTS = 30,
    WSG_STATUS_COUNT
} wsg_status_t;

/* Appendix A's description ("Range error"); "Unknown error" outside the table. */
const char *wsg_status_description(wsg_status_t status);

#endif
