/* SPDX-License-Identifier: BSD-3-Clause */
#include "bin_coverage.h"

#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "wsg/wsg_names.h"
#include "wsg/wsg_bin.h"

#define FRAME_MIN 10u /* header, status, CRC */
#define ID_SYSTEM_STATE 0x40u
#define VALUES_AT 8u /* preamble, ID, length, status */

void bin_coverage_reset(bin_coverage_t *bcov)
{
    memset(bcov, 0, sizeof(*bcov));
}

void bin_coverage_add(bin_coverage_t *total, const bin_coverage_t *part)
{
    for (unsigned id = 0; id < BIN_COVERAGE_IDS; id++) {
        total->frames[id] += part->frames[id];
        total->statuses[id] |= part->statuses[id];
    }
    for (unsigned s = 0; s < WSG_STATUS_COUNT; s++) {
        total->status_count[s] += part->status_count[s];
    }
    total->flags_observed |= part->flags_observed;
}

void bin_coverage_frame_out(bin_coverage_t *bcov, const unsigned char *frame, size_t len)
{
    if (len < FRAME_MIN || frame[0] != 0xAAu) {
        return;
    }
    unsigned id = frame[3];
    unsigned status = (unsigned)frame[6] | (unsigned)frame[7] << 8;
    bcov->frames[id]++;
    if (status < WSG_STATUS_COUNT) {
        bcov->statuses[id] |= 1UL << status;
        bcov->status_count[status]++;
    }
    if (id == ID_SYSTEM_STATE && status == E_SUCCESS && len >= VALUES_AT + 4u + 2u) {
        const unsigned char *v = frame + VALUES_AT;
        bcov->flags_observed |=
            (uint32_t)v[0] | (uint32_t)v[1] << 8 | (uint32_t)v[2] << 16 | (uint32_t)v[3] << 24;
    }
}

static void id_label(unsigned id, char *out, size_t cap)
{
    const char *name = wsg_bin_command_name((uint8_t)id);
    snprintf(out, cap, "0x%02X%s%s", id, name != NULL ? " " : "", name != NULL ? name : "");
}

static cJSON *status_names(uint32_t bits)
{
    cJSON *names = cJSON_CreateArray();
    for (unsigned s = 0; s < WSG_STATUS_COUNT; s++) {
        if ((bits >> s) & 1u) {
            cJSON_AddItemToArray(names, cJSON_CreateString(wsg_status_name((wsg_status_t)s)));
        }
    }
    return names;
}

static cJSON *report_statuses(const bin_coverage_t *bcov)
{
    cJSON *out = cJSON_CreateArray();
    for (unsigned s = 0; s < WSG_STATUS_COUNT; s++) {
        if (bcov->status_count[s] > 0) {
            cJSON *item = cJSON_CreateObject();
            cJSON_AddStringToObject(item, "name", wsg_status_name((wsg_status_t)s));
            cJSON_AddNumberToObject(item, "count", bcov->status_count[s]);
            cJSON_AddItemToArray(out, item);
        }
    }
    return out;
}

/* The system flags by whether a client saw them set in a state reply. */
static void report_flags_observed(const bin_coverage_t *bcov, cJSON *out, cJSON *summary)
{
    cJSON *seen = cJSON_CreateArray();
    cJSON *never = cJSON_CreateArray();
    unsigned count = 0;
    for (unsigned bit = 0; bit < WSG_SYSFLAG_COUNT; bit++) {
        const char *name = wsg_sysflag_name(bit);
        if (name == NULL) {
            continue;
        }
        bool on = ((bcov->flags_observed >> bit) & 1u) != 0u;
        count += on ? 1u : 0u;
        cJSON_AddItemToArray(on ? seen : never, cJSON_CreateString(name));
    }
    cJSON_AddItemToObject(out, "flags_observed", seen);
    cJSON_AddItemToObject(out, "flags_never_observed", never);
    cJSON_AddNumberToObject(summary, "binary_flags_observed", count);
}

/* Statuses the firmware itself answers for an ID it does not serve; any
 * other status under such an ID came from a user script (docs/scripting.md). */
#define FIRMWARE_ONLY_STATUSES                                                                     \
    ((1UL << E_CMD_UNKNOWN) | (1UL << E_CHECKSUM_ERROR) | (1UL << E_ACCESS_DENIED) |               \
     (1UL << E_OVERRUN) | (1UL << E_CMD_FORMAT_ERROR))

cJSON *bin_coverage_report(const bin_coverage_t *bcov, cJSON *summary)
{
    cJSON *used = cJSON_CreateArray();
    cJSON *never = cJSON_CreateArray();
    cJSON *unknown = cJSON_CreateArray();
    cJSON *custom = cJSON_CreateArray();
    unsigned total = 0;
    unsigned covered = 0;
    for (unsigned id = 0; id < BIN_COVERAGE_IDS; id++) {
        char label[48];
        bool known = wsg_bin_command_name((uint8_t)id) != NULL;
        id_label(id, label, sizeof(label));
        total += known ? 1u : 0u;
        if (bcov->frames[id] == 0) {
            if (known) {
                cJSON_AddItemToArray(never, cJSON_CreateString(label));
            }
            continue;
        }
        covered += known ? 1u : 0u;
        cJSON *item = cJSON_CreateObject();
        cJSON_AddStringToObject(item, "id", label);
        cJSON_AddNumberToObject(item, "frames", bcov->frames[id]);
        cJSON_AddItemToObject(item, "statuses", status_names(bcov->statuses[id]));
        bool scripted = !known && (bcov->statuses[id] & ~FIRMWARE_ONLY_STATUSES) != 0u;
        cJSON_AddItemToArray(known ? used : scripted ? custom : unknown, item);
    }
    cJSON *out = cJSON_CreateObject();
    cJSON_AddItemToObject(out, "used", used);
    cJSON_AddItemToObject(out, "never_used", never);
    cJSON_AddItemToObject(out, "unknown_ids_sent", unknown);
    cJSON_AddItemToObject(out, "custom_ids_answered", custom);
    cJSON_AddItemToObject(out, "statuses_returned", report_statuses(bcov));
    report_flags_observed(bcov, out, summary);
    cJSON_AddNumberToObject(summary, "binary_commands_total", total);
    cJSON_AddNumberToObject(summary, "binary_commands_used", covered);
    return out;
}
