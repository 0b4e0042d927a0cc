/* --trace: every GCL line in and out on stderr, with time and session. */
#ifndef HOST_TRACE_H
#define HOST_TRACE_H

#include <stdbool.h>

#include "wsg_device.h"

/* The trace's observers, for a module that fans the device hooks out. */
const wsg_device_hooks_t *trace_device_hooks(void);
/* --strict: input the manual does not allow, as a trace line marked '!'. */
void trace_tolerated(const wsg_session_t *s, const char *name, const char *what);

#endif
