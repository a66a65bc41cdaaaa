/* The atmosphere file (SPEC §4): JSON in, a validated sf_atmosphere out, and
 * back to one canonical JSON text whose hash identifies the atmosphere (so a
 * renderer's build can tell when its shader constants are stale).
 *
 * Errors are SF_ERR_INPUT with a one-line message
 * "<source>: <key path>: <problem>", e.g.
 * "hazy.json: constituents[1].phase.g: |g| must be < 1, got 1.2".
 * In a file with "base": "default", a key that the file does not set but
 * inherits from the default is named "(base default) <key path>", with the
 * index it has in the default's constituent list. */
#ifndef SKYFIT_MODELS_ATMOSPHERE_FILE_H
#define SKYFIT_MODELS_ATMOSPHERE_FILE_H

#include <stddef.h>
#include <stdint.h>

#include "models/atmosphere.h"
#include "util/error.h"

/* Used when a file gives no sun_angular_radius_rad: the Sun seen from Earth. */
#define SF_DEFAULT_SUN_ANGULAR_RADIUS_RAD 0.004675

/* Parse and validate; on failure fill err (SF_ERR_INPUT) and return nonzero;
 * *out is untouched on failure. On success *out is finalized
 * (sf_atmosphere_finalize) and every unused array entry is zero. */
int sf_atmosphere_load_file(const char *path, sf_atmosphere *out, sf_error *err);
/* source_name names the text in messages (NULL: "<string>"). */
int sf_atmosphere_load_string(const char *json_text, const char *source_name,
                              sf_atmosphere *out, sf_error *err);

/* The built-in default (Hillaire 2020 Earth): exactly the file of SPEC §4. */
void sf_atmosphere_default(sf_atmosphere *out);
const char *sf_atmosphere_default_json(void);

/* Canonical JSON of a loaded atmosphere: fixed key order, numbers as %.17g,
 * every field explicit (a purely absorbing constituent has no "phase"), no
 * "base", ends with a newline. Loading it gives back an identical struct.
 * malloc'd, caller frees; NULL only when out of memory. */
char *sf_atmosphere_to_json(const sf_atmosphere *atm);

/* 64-bit FNV-1a of the canonical JSON text (computed without allocating). */
uint64_t sf_atmosphere_hash(const sf_atmosphere *atm);
/* The hash as 16 lower-case hex digits and a terminating NUL. */
void sf_atmosphere_hash_hex(const sf_atmosphere *atm, char out[17]);

#endif
