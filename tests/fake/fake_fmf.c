/* SPDX-License-Identifier: BSD-3-Clause */
/* A WSG-FMF finger in slot 0 for the device tests: the simulated finger node
 * (hal/sim/finger_node.c) and the device's controller on a minimal in-test
 * bus, driven by the harness' virtual clock. */
#include <string.h>

#include "finger_node.h"
#include "fake_device.h"

#define FMF_RING 64u

static struct {
    finger_node_t node;
    hal_can_filter_t node_filters[HAL_CAN_MAX_FILTERS];
    unsigned node_filter_count;
    hal_can_filter_t device_filters[HAL_CAN_MAX_FILTERS];
    unsigned device_filter_count;
    hal_can_frame_t ring[FMF_RING]; /* frames waiting for the device */
    unsigned head, count;
} fmf;

static bool node_send(void *ctx, const hal_can_frame_t *frame)
{
    (void)ctx;
    if (!hal_can_filters_accept(fmf.device_filters, fmf.device_filter_count, frame)) {
        return true;
    }
    ck_assert_uint_lt(fmf.count, FMF_RING);
    fmf.ring[(fmf.head + fmf.count) % FMF_RING] = *frame;
    fmf.count++;
    return true;
}

static bool no_recv(void *ctx, hal_can_frame_t *frame)
{
    (void)ctx;
    (void)frame;
    return false;
}

static bool no_filters(void *ctx, const hal_can_filter_t *filters, unsigned count)
{
    (void)ctx;
    (void)filters;
    (void)count;
    return true;
}

static const hal_can_ops_t node_ops = {node_send, no_recv, no_filters, false,
                                       NULL,      NULL,    NULL,       NULL};
static const hal_can_t node_port = {&node_ops, NULL};

static bool device_send(void *ctx, const hal_can_frame_t *frame)
{
    (void)ctx;
    if (hal_can_filters_accept(fmf.node_filters, fmf.node_filter_count, frame)) {
        wsg_finger_node_receive(&fmf.node, frame, h_now_us);
    }
    return true;
}

/* The node catches up with the clock before the device polls. */
static bool device_recv(void *ctx, hal_can_frame_t *frame)
{
    (void)ctx;
    if (fmf.count == 0u) {
        wsg_finger_node_step(&fmf.node, h_now_us);
    }
    if (fmf.count == 0u) {
        return false;
    }
    *frame = fmf.ring[fmf.head];
    fmf.head = (fmf.head + 1u) % FMF_RING;
    fmf.count--;
    return true;
}

static bool device_set_filters(void *ctx, const hal_can_filter_t *filters, unsigned count)
{
    (void)ctx;
    ck_assert_uint_le(count, HAL_CAN_MAX_FILTERS);
    memcpy(fmf.device_filters, filters, count * sizeof(filters[0]));
    fmf.device_filter_count = count;
    return true;
}

static const hal_can_ops_t device_ops = {
    device_send, device_recv, device_set_filters, false, NULL, NULL, NULL, NULL};

void h_setup_fmf_homed(void)
{
    h_setup();
    memset(&fmf, 0, sizeof(fmf));
    finger_node_params_t params;
    wsg_finger_node_defaults(&params);
    wsg_finger_node_init(&fmf.node, FBUS_TYPE_FMF, 0, &params, &node_port);
    fmf.node_filter_count = wsg_finger_node_filters(&fmf.node, fmf.node_filters);
    h_devp()->hal.can = (hal_can_t){&device_ops, NULL}; /* the bus wired in after power-on */
    wsg_finger_bus_init(&h_devp()->fbus, &h_devp()->hal.can);
    advance_ms(200); /* the finger boots and delivers data */
    ck_assert_int_eq(ask_flag(SF_FORCECNTL_MODE), 1);
    SEND("HOME()");
    EXPECT("ACK HOME");
    ck_assert_int_ge(run_until_line(&h_main, "FIN HOME", 5000), 0);
    EXPECT_NONE();
}
