/* --trace: every GCL line in and out on stderr, with time and session. */
#ifndef HOST_TRACE_H
#define HOST_TRACE_H

#include <stdbool.h>

#include "wsg_device.h"

void trace_attach(wsg_device_t *dev, bool enabled);

#endif
