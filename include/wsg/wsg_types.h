/* SPDX-License-Identifier: BSD-3-Clause */
/* Shared enumerations of the device model (Appendices B, C and D). */
#ifndef WSG_TYPES_H
#define WSG_TYPES_H

/* Appendix D */
typedef enum {
    GS_IDLE = 0,
    GS_GRASPING = 1,
    GS_NO_PART = 2,
    GS_PART_LOST = 3,
    GS_HOLDING = 4,
    GS_RELEASING = 5,
    GS_POSITIONING = 6,
    GS_ERROR = 7,
    GS_COUNT
} wsg_grip_state_t;

/* Appendix B: bit numbers of the system state flags */
typedef enum {
    SF_REFERENCED = 0,
    SF_MOVING = 1,
    SF_BLOCKED_MINUS = 2,
    SF_BLOCKED_PLUS = 3,
    SF_SOFT_LIMIT_MINUS = 4,
    SF_SOFT_LIMIT_PLUS = 5,
    SF_AXIS_STOPPED = 6,
    SF_TARGET_POS_REACHED = 7,
    SF_OVERDRIVE_MODE = 8,
    SF_FORCECNTL_MODE = 9,
    SF_FAST_STOP = 12,
    SF_TEMP_WARNING = 13,
    SF_TEMP_FAULT = 14,
    SF_POWER_FAULT = 15,
    SF_CURR_FAULT = 16,
    SF_FINGER_FAULT = 17,
    SF_CMD_FAILURE = 18,
    SF_SCRIPT_RUNNING = 19,
    SF_SCRIPT_FAILURE = 20,
} wsg_sysflag_t;

#define WSG_SYSFLAG_COUNT 32
#define WSG_FLAG(bit) (1UL << (bit))

/* Appendix C: bit numbers of the finger flags */
typedef enum {
    FF_POWER_ON = 0,
    FF_CONFIG_AVAIL = 1,
    FF_COMM_OPEN = 2,
    FF_POWER_FAULT = 8,
    FF_COMM_FAULT = 9,
    FF_INIT_FAULT = 10,
} wsg_finger_flag_t;

#define WSG_FINGER_FLAG_COUNT 16
#define WSG_FINGER_COUNT 2

/* Values AUTOSEND can stream */
typedef enum {
    AS_POS,
    AS_SPEED,
    AS_FORCE,
    AS_GRIPSTATE,
    AS_SYSFLAGS,
    AS_TEMP,
    AS_COUNT
} wsg_autosend_value_t;

#endif
