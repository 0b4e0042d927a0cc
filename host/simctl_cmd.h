/* The simulation control commands (docs/simctl.md): one line in, one reply
 * line out, with the lexical rules of GCL. */
#ifndef SIMCTL_CMD_H
#define SIMCTL_CMD_H

#include <stdbool.h>
#include <stddef.h>

/* Runs one control line (without its terminator) and returns the reply line
 * (malloc'd, no '\n'): "ACK NAME", "NAME=value" or "ERR NAME code reason".
 * *close (if given) becomes true when the line asked to end the channel. */
char *simctl_exec(const char *line, size_t len, bool *close);

/* True when the line is a known control command in a form it accepts, with
 * valid arguments (checked without acting; a session id only for its form);
 * else why not. for_scenario also refuses commands a scenario cannot run. */
bool simctl_check(const char *line, size_t len, bool for_scenario, char *why, size_t cap);

#endif
