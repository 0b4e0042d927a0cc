/* SPDX-License-Identifier: BSD-3-Clause */
/* Simulated finger nodes (finger_node.h). */
#include "finger_node.h"

#include <string.h>

#define FMF_AVERAGE_ALPHA 0.3f
#define DSA_FORCE_MIN_N 0.05f
#define DSA_PEAK_BASE 300.0f
#define DSA_PEAK_PER_N 45.0f
#define NODE_FIRMWARE 0x0100u    /* 1.0 */
#define NOISE_SUM_SIGMA 0.57735f /* standard deviation of a sum of 4 uniform(-0.5, 0.5) */

void wsg_finger_node_defaults(finger_node_params_t *params)
{
    params->offset_n = 0.6f;
    params->noise_n = 0.02f;
    params->seed = 0;
}

void wsg_finger_node_init(finger_node_t *node, fbus_type_t type, unsigned slot,
                          const finger_node_params_t *params, const hal_can_t *bus)
{
    memset(node, 0, sizeof(*node));
    node->type = type;
    node->node = FBUS_NODE_ID(slot);
    node->slot = (uint8_t)slot;
    node->params = *params;
    node->bus = bus;
    node->rng = params->seed != 0u ? params->seed : 0x9E3779B9u ^ (uint32_t)(slot + 1u);
}

unsigned wsg_finger_node_filters(const finger_node_t *node, hal_can_filter_t *out)
{
    out[0] = (hal_can_filter_t){FBUS_ID_STATE, HAL_CAN_STD_ID_MASK, 0};
    out[1] = (hal_can_filter_t){wsg_fbus_id(FBUS_ID_COMMAND, node->node), HAL_CAN_STD_ID_MASK, 0};
    out[2] = (hal_can_filter_t){wsg_fbus_id(FBUS_ID_SIMCTL, node->node), HAL_CAN_STD_ID_MASK, 0};
    return 3;
}

static void send(finger_node_t *node, const hal_can_frame_t *frame)
{
    if (hal_can_send(node->bus, frame)) {
        node->frames_sent++;
    }
}

static bool faulted(const finger_node_t *node)
{
    return (node->sim_faults & (FBUS_FAULT_POWER | FBUS_FAULT_INIT)) != 0u;
}

static bool present(const finger_node_t *node)
{
    return node->type != FBUS_TYPE_NONE && (node->sim_faults & FBUS_FAULT_UNPLUG) == 0u;
}

static void send_heartbeat(finger_node_t *node)
{
    fbus_heartbeat_t hb = {FBUS_NODE_OPERATIONAL,
                           node->sim_faults & (FBUS_FAULT_POWER | FBUS_FAULT_INIT),
                           node->heartbeat_counter++};
    if (!node->operational) {
        hb.state = FBUS_NODE_BOOT;
    } else if (faulted(node)) {
        hb.state = FBUS_NODE_FAULT;
    }
    hal_can_frame_t f;
    wsg_fbus_pack_heartbeat(&f, node->node, &hb);
    send(node, &f);
}

static void describe(const finger_node_t *node, fbus_descriptor_t *d)
{
    memset(d, 0, sizeof(*d));
    d->type = (uint8_t)node->type;
    d->version = FBUS_PROTO_VERSION;
    d->firmware = NODE_FIRMWARE;
    if (node->type == FBUS_TYPE_FMF) {
        d->rows = 1;
        d->cols = 1;
        d->encoding = FBUS_ENC_MEASURE;
        d->features = FBUS_FEATURE_TARE;
    } else if (node->type == FBUS_TYPE_DSA) {
        d->rows = FBUS_DSA_ROWS;
        d->cols = FBUS_DSA_COLS;
        d->encoding = FBUS_ENC_BULK;
    }
}

static void send_descriptor(finger_node_t *node)
{
    if (!node->operational || (node->sim_faults & FBUS_FAULT_INIT) != 0u) {
        return; /* the descriptor memory could not be read */
    }
    fbus_descriptor_t d;
    describe(node, &d);
    hal_can_frame_t f;
    wsg_fbus_pack_descriptor(&f, node->node, &d);
    send(node, &f);
}

static void power_on(finger_node_t *node, uint64_t now_us)
{
    node->powered = true;
    node->operational = false;
    node->powered_at_us = now_us;
    node->next_heartbeat_us = now_us;
    node->next_data_us = now_us + FBUS_BOOT_US;
    node->tared = false;
    node->tare_n = 0.0f;
    node->average_n = node->params.offset_n;
}

/* xorshift32 */
static uint32_t next_random(finger_node_t *node)
{
    uint32_t x = node->rng;
    x ^= x << 13;
    x ^= x >> 17;
    x ^= x << 5;
    node->rng = x;
    return x;
}

/* Approximately normal, zero mean, standard deviation sigma. */
static float noise(finger_node_t *node, float sigma)
{
    float sum = 0.0f;
    for (int i = 0; i < 4; i++) {
        sum += (float)(next_random(node) >> 8) / 16777216.0f - 0.5f;
    }
    return sum * sigma / NOISE_SUM_SIGMA;
}

static void tare(finger_node_t *node)
{
    if (node->type != FBUS_TYPE_FMF || !node->operational || faulted(node)) {
        return;
    }
    node->tare_n = node->average_n;
    node->tared = true;
    node->tare_count++;
}

static void on_state(finger_node_t *node, const fbus_state_t *s, uint64_t now_us)
{
    node->state = *s;
    node->have_state = true;
    node->last_state_us = now_us;
    bool supplied = (s->power_mask & (1u << (node->node - 1u))) != 0u;
    if (supplied && !node->powered) {
        power_on(node, now_us);
    } else if (!supplied) {
        node->powered = false;
    }
}

static void on_simctl(finger_node_t *node, uint8_t faults, uint64_t now_us)
{
    bool was_init_fault = (node->sim_faults & FBUS_FAULT_INIT) != 0u;
    if (faults != node->sim_faults) {
        node->next_heartbeat_us = now_us; /* a changed state is announced at once */
    }
    node->sim_faults = faults;
    if ((faults & FBUS_FAULT_UNPLUG) != 0u) {
        node->powered = false; /* off the connector: no supply, no bus */
    } else if (was_init_fault && (faults & FBUS_FAULT_INIT) == 0u && node->powered) {
        send_descriptor(node);
    }
}

/* The frame's function code says what it can be: one unpack, not a try of
 * each (STATE comes every 10 ms). */
static void handle_frame(finger_node_t *node, const hal_can_frame_t *frame, uint64_t now_us)
{
    fbus_state_t state;
    uint8_t value = 0;
    bool mine = fbus_node_of(frame->id) == node->node;
    switch (fbus_func_of(frame->id)) {
    case FBUS_ID_SIMCTL:
        if (mine && wsg_fbus_unpack_simctl(frame, &value)) {
            on_simctl(node, value, now_us);
        }
        break;
    case FBUS_ID_STATE:
        if (present(node) && wsg_fbus_unpack_state(frame, &state)) {
            on_state(node, &state, now_us);
        }
        break;
    case FBUS_ID_COMMAND:
        if (present(node) && node->powered && mine && wsg_fbus_unpack_command(frame, &value)) {
            if (value == FBUS_CMD_TARE) {
                tare(node);
            } else if (value == FBUS_CMD_REQ_DESCRIPTOR) {
                send_descriptor(node);
            }
        }
        break;
    default:
        break;
    }
}

void wsg_finger_node_receive_state(finger_node_t *node, const fbus_state_t *s, uint64_t now_us)
{
    bool was_powered = node->powered;
    if (present(node)) {
        on_state(node, s, now_us);
    }
    if (!was_powered || !node->powered) { /* as in wsg_finger_node_receive() */
        node->due_us = wsg_finger_node_next_due_us(node);
    }
}

void wsg_finger_node_receive(finger_node_t *node, const hal_can_frame_t *frame, uint64_t now_us)
{
    bool was_powered = node->powered;
    handle_frame(node, frame, now_us);
    /* A STATE that keeps the node powered (one every 10 ms) moves only its
     * supply timeout, and only later: the due time it had stays early
     * enough. Any other frame may power it, or wake it. */
    bool kept_powered = was_powered && node->powered && fbus_func_of(frame->id) == FBUS_ID_STATE;
    if (!kept_powered) {
        node->due_us = wsg_finger_node_next_due_us(node);
    }
}

void wsg_finger_node_set_contact(finger_node_t *node, const finger_contact_t *contact)
{
    node->contact = contact;
    node->cells_valid = false;
}

/* The force on the finger: its own contact's, else the broadcast one. */
static float contact_force(const finger_node_t *node, float *cells_n)
{
    if (node->contact != NULL) {
        float force = 0.0f;
        node->contact->read(node->contact->ctx, node->slot, &force, cells_n);
        return force;
    }
    return node->have_state ? node->state.force_n : 0.0f;
}

static float fmf_reading(finger_node_t *node)
{
    float cells[FBUS_DSA_ROWS * FBUS_DSA_COLS];
    float contact = contact_force(node, cells);
    float raw = contact + node->params.offset_n + noise(node, node->params.noise_n);
    node->average_n += FMF_AVERAGE_ALPHA * (raw - node->average_n);
    return raw - node->tare_n;
}

static void send_fmf(finger_node_t *node)
{
    float value = fmf_reading(node);
    float milli = value * 1000.0f;
    fbus_measure_t m = {(int32_t)(milli < 0.0f ? milli - 0.5f : milli + 0.5f), node->data_counter++,
                        node->tared ? FBUS_MEASURE_TARED : 0u, node->tare_count};
    hal_can_frame_t f;
    wsg_fbus_pack_measure(&f, node->node, &m);
    send(node, &f);
}

static float sqrt_approx(float x)
{
    if (x <= 0.0f) {
        return 0.0f;
    }
    float r = x > 1.0f ? x : 1.0f;
    for (int i = 0; i < 12; i++) {
        r = 0.5f * (r + x / r);
    }
    return r;
}

/* A round contact patch in the middle of the pad: it widens with the square
 * root of the force (elastic contact) and its peak rises with the force. */
void wsg_finger_node_dsa_pattern(float force_n, uint16_t *cells)
{
    memset(cells, 0, sizeof(uint16_t) * FBUS_DSA_ROWS * FBUS_DSA_COLS);
    if (force_n < DSA_FORCE_MIN_N) {
        return;
    }
    float radius = 1.0f + 0.6f * sqrt_approx(force_n);
    float peak = DSA_PEAK_BASE + DSA_PEAK_PER_N * force_n;
    peak = peak > (float)FBUS_DSA_CELL_MAX ? (float)FBUS_DSA_CELL_MAX : peak;
    float r0 = ((float)FBUS_DSA_ROWS - 1.0f) / 2.0f;
    float c0 = ((float)FBUS_DSA_COLS - 1.0f) / 2.0f;
    for (unsigned r = 0; r < FBUS_DSA_ROWS; r++) {
        for (unsigned c = 0; c < FBUS_DSA_COLS; c++) {
            float dr = (float)r - r0;
            float dc = (float)c - c0;
            float share = 1.0f - (dr * dr + dc * dc) / (radius * radius);
            cells[r * FBUS_DSA_COLS + c] = share > 0.0f ? (uint16_t)(peak * share + 0.5f) : 0u;
        }
    }
}

#define DSA_SEGMENTS FINGER_NODE_DSA_SEGMENTS
#define DSA_VALUES                                                                                 \
    (DSA_SEGMENTS * FBUS_BULK_VALUES_PER_FRAME) /* the cells, the last segment padded */

/* The pattern follows the contact force alone: worked out again only when
 * the force the gripper broadcast changed since the last transfer, and
 * kept as it goes on the wire. */
/* A cell's value for the force on it (N): a pad's cells read 0-4095 over
 * 0-1.4 N each. */
#define DSA_CELL_PER_N 3000.0f

static void contact_cells(finger_node_t *node)
{
    float cells_n[FBUS_DSA_ROWS * FBUS_DSA_COLS];
    (void)contact_force(node, cells_n);
    uint16_t cells[DSA_VALUES] = {0};
    for (unsigned i = 0; i < FBUS_DSA_ROWS * FBUS_DSA_COLS; i++) {
        float value = cells_n[i] * DSA_CELL_PER_N + 0.5f;
        cells[i] = value > (float)FBUS_DSA_CELL_MAX ? (uint16_t)FBUS_DSA_CELL_MAX
                                                    : (value > 1.0f ? (uint16_t)value : 0u);
    }
    wsg_fbus_bulk_wire(node->cells_wire, cells, DSA_VALUES);
    node->cells_valid = false; /* the scene's contact changes on its own */
}

static void update_dsa_cells(finger_node_t *node)
{
    if (node->contact != NULL) {
        contact_cells(node);
        return;
    }
    float force_n = node->have_state ? node->state.force_n : 0.0f;
    if (node->cells_valid && force_n == node->cells_force_n) {
        return;
    }
    uint16_t cells[DSA_VALUES] = {0};
    wsg_finger_node_dsa_pattern(force_n, cells);
    wsg_fbus_bulk_wire(node->cells_wire, cells, DSA_VALUES);
    node->cells_force_n = force_n;
    node->cells_valid = true;
}

/* A transfer's frames go out in one burst. */
static void send_dsa(finger_node_t *node)
{
    update_dsa_cells(node);
    uint8_t transfer = node->data_counter++;
    hal_can_frame_t frames[DSA_SEGMENTS];
    wsg_fbus_pack_bulk_transfer(frames, node->node, transfer, node->cells_wire, DSA_SEGMENTS);
    node->frames_sent += hal_can_send_many(node->bus, frames, DSA_SEGMENTS);
}

/* The next time of a periodic event that was due at `due`. */
static uint64_t reschedule(uint64_t due, uint32_t period, uint64_t now_us)
{
    uint64_t next = due + period;
    return next <= now_us ? now_us + period : next;
}

static void send_data(finger_node_t *node, uint64_t now_us)
{
    if (node->type == FBUS_TYPE_FMF) {
        send_fmf(node);
        node->next_data_us = reschedule(node->next_data_us, FBUS_MEASURE_PERIOD_US, now_us);
    } else if (node->type == FBUS_TYPE_DSA) {
        send_dsa(node);
        node->next_data_us = reschedule(node->next_data_us, FBUS_BULK_PERIOD_US, now_us);
    } else {
        node->next_data_us = UINT64_MAX;
    }
}

static void run_due(finger_node_t *node, uint64_t now_us)
{
    if (node->powered && now_us - node->last_state_us > FBUS_SUPPLY_TIMEOUT_US) {
        node->powered = false; /* the gripper is gone: no supply */
    }
    if (!node->powered || !present(node)) {
        return;
    }
    if (!node->operational && now_us - node->powered_at_us >= FBUS_BOOT_US) {
        node->operational = true;
        node->next_heartbeat_us = now_us;
        send_descriptor(node);
    }
    if (now_us >= node->next_heartbeat_us) {
        send_heartbeat(node);
        node->next_heartbeat_us =
            reschedule(node->next_heartbeat_us, FBUS_HEARTBEAT_PERIOD_US, now_us);
    }
    if (node->operational && !faulted(node) && now_us >= node->next_data_us) {
        send_data(node, now_us);
    }
}

uint64_t wsg_finger_node_next_due_us(const finger_node_t *node)
{
    if (!node->powered || !present(node)) {
        return UINT64_MAX;
    }
    uint64_t due = node->next_heartbeat_us;
    if (!node->operational) {
        uint64_t boot = node->powered_at_us + FBUS_BOOT_US;
        due = boot < due ? boot : due;
    } else if (!faulted(node) && node->next_data_us < due) {
        due = node->next_data_us;
    }
    uint64_t supply = node->last_state_us + FBUS_SUPPLY_TIMEOUT_US + 1u;
    return supply < due ? supply : due;
}

void wsg_finger_node_step_due(finger_node_t *node, uint64_t now_us)
{
    run_due(node, now_us);
    node->due_us = wsg_finger_node_next_due_us(node);
}

static bool same_word(const char *a, const char *word, size_t len)
{
    for (size_t i = 0; i < len; i++) {
        char c = a[i];
        if (c >= 'A' && c <= 'Z') {
            c = (char)(c - 'A' + 'a');
        }
        if (c != word[i] || word[i] == '\0') {
            return false;
        }
    }
    return word[len] == '\0';
}

static bool parse_word(const char *text, size_t len, fbus_type_t *type)
{
    static const char *const names[] = {"none", "generic", "fmf", "dsa"};
    for (unsigned i = 0; i < 4u; i++) {
        if (same_word(text, names[i], len)) {
            *type = (fbus_type_t)i;
            return true;
        }
    }
    return false;
}

bool wsg_finger_node_parse_pair(const char *text, fbus_type_t types[FBUS_SLOTS])
{
    const char *comma = strchr(text, ',');
    types[1] = FBUS_TYPE_NONE;
    if (comma == NULL) {
        return parse_word(text, strlen(text), &types[0]);
    }
    return parse_word(text, (size_t)(comma - text), &types[0]) &&
           parse_word(comma + 1, strlen(comma + 1), &types[1]);
}
