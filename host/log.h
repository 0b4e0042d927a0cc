/* Host logging: hal_log() and the server's own messages go to stderr. */
#ifndef HOST_LOG_H
#define HOST_LOG_H

#include "hal_log.h"

void host_log_set_verbose(int verbose);
void host_logf(hal_log_level_t level, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

#endif
