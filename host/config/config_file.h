/* SPDX-License-Identifier: BSD-3-Clause */
/* --config FILE: the settings the real WSG keeps in its configuration memory
 * and edits through its web interface, in INI form (parsed with libinih).
 * docs/wsgsim.example.ini lists every key. */
#ifndef HOST_CONFIG_FILE_H
#define HOST_CONFIG_FILE_H

/* Where the installed example configuration lies, named by --help (and so
 * the man page) and by an unknown key's error: the build sets this
 * install's path (mk/install.mk); this default is `make install`'s. */
#ifndef WSGSIM_EXAMPLE_CONFIG
#define WSGSIM_EXAMPLE_CONFIG "/usr/local/share/doc/wsgsim/examples/wsgsim.example.ini"
#endif

#include <stdbool.h>
#include <stddef.h>

#include "host_options.h"
#include "wsg/wsg_config.h"

/* config_file_t (declared in host_options.h, whose host_options_t points to the
 * one options_parse() read): what the files read hold. Nothing read yet;
 * NULL: out of memory. */
config_file_t *config_file_create(void);
void config_file_destroy(config_file_t *cf);

/* Reads the --config file, then the --save-file (either may be NULL; a save
 * file that does not exist yet is nothing saved): a key the save file sets
 * overrides the configuration's. Host settings (ports, clients, ...) go into
 * opts, device settings are kept for config_file_apply(). On an unknown
 * section or key or a bad value prints "wsgsim: FILE:LINE: ..." and returns
 * false. */
bool config_file_load(config_file_t *cf, const char *config_path, const char *save_path,
                      host_options_t *opts);
/* The functions below take the instance first; the queries and the apply
 * functions take NULL for no file read (nothing set). */
/* Checks the device settings against the model's ranges (same message form). */
bool config_file_check(config_file_t *cf, const char *model);
/* Overrides the model's factory configuration with the file's settings. */
void config_file_apply(const config_file_t *cf, wsg_config_t *cfg);
/* The [device.N] sections (a fleet's devices declared one by one): how many
 * devices they declare (highest N + 1; 0: none), device index's model (or
 * fallback), its ports (false: not given) and its identity (serial, tag),
 * applied over what config_file_apply() and the fleet's numbering set. */
unsigned config_file_devices(const config_file_t *cf);
const char *config_file_device_model(const config_file_t *cf, unsigned index, const char *fallback);
bool config_file_device_port(const config_file_t *cf, unsigned index, bool udp, int *port);
/* [device.N] script: device index's startup script (or fallback). */
const char *config_file_device_script(const config_file_t *cf, unsigned index,
                                      const char *fallback);
/* True when the saved settings (the --save-file, which the web page's Save
 * writes) decide device index's startup script: script, the file in force
 * for it (a text this file holds, compared by address, not by name), is
 * the save file's, or the save file switched the autostart off. Such a
 * file that is missing does not stop a start (docs/scripting.md). */
bool config_file_startup_saved(const config_file_t *cf, unsigned index, const char *script);
/* [device.N] fingers: device index's loopback fingers ("fmf,dsa", or fallback). */
const char *config_file_device_fingers(const config_file_t *cf, unsigned index,
                                       const char *fallback);
void config_file_apply_device(const config_file_t *cf, unsigned index, wsg_config_t *cfg);
/* True when a [device.N] section for device index sets its tag (which then
 * wins over [device]'s). */
bool config_file_device_sets_tag(const config_file_t *cf, unsigned index);
/* Saves the device's settings in force to the file at path (the web page's
 * Save): the [motion] keys, [network] disconnect_faststop and binary_crc,
 * and the tag ([device] for device 0, [device.N] for another). Keys already
 * in the file get the new value in place; missing ones are added to their
 * section, missing sections at the end; every other line stays as it was.
 * A file that does not exist yet is created. The file is replaced at once
 * (written and synced beside it, then renamed). False with the reason in
 * why. */
/* startup: the startup script the web page chose ("/user/NAME"), "" when
 * it chose none (then device 0 saves autostart = no), NULL to leave the
 * file's as they are. */
/* cf: the files read at start (NULL: none), whose models the settings must
 * fit. */
bool config_file_save(const config_file_t *cf, const char *path, unsigned device,
                      const wsg_config_t *cfg, const char *startup, char *why, size_t cap);
/* True when cfg's [motion] settings, written as the file's global ones, fit
 * every model the loaded file's next start checks them against (the
 * devices' model and each [device.N] model); else false with the reason in
 * why. config_file_save() refuses settings that do not: a fleet of mixed
 * models would not start from the file it wrote. */
bool config_file_motion_fits(const config_file_t *cf, const wsg_config_t *cfg, char *why,
                             size_t cap);

#endif
