/* Likely unit mistakes in a loaded atmosphere (SPEC §3: lengths in km,
 * coefficients in 1/km, angles in radians). SPEC §4 keeps every such value
 * legal, so these are warnings, not errors: radii in metres, a sun radius in
 * degrees, coefficients or scale factors per metre, a decaying profile
 * written with a positive exp_scale_per_km, layer widths in metres,
 * wavelengths in micrometres. The thresholds sit outside every real sky:
 * Earth, Mars, Venus, Titan, Jupiter-sized and SPEC §10's extreme scale
 * heights (0.01-100 km) stay silent.
 *
 * Each warning is one line "<source>: <key> = <value>: <why>; <what was
 * probably meant>", e.g. "a.json: bottom_radius_km = 6.36e+06: a planet of
 * 6.4 million km ...". Constituents are named by their name, which is
 * unique and the same in a file over "base": "default" as in its merge. */
#ifndef SKYFIT_MODELS_ATMOSPHERE_UNITS_H
#define SKYFIT_MODELS_ATMOSPHERE_UNITS_H

#include "models/atmosphere.h"

#define SF_UNIT_WARNINGS_MAX 16
#define SF_UNIT_WARNING_LEN 512

typedef struct sf_unit_warnings {
  int count;     /* lines in text */
  int dropped;   /* further warnings found beyond SF_UNIT_WARNINGS_MAX */
  char text[SF_UNIT_WARNINGS_MAX][SF_UNIT_WARNING_LEN];
} sf_unit_warnings;

/* The warnings for atm, whose file is named source in them. Pure: reads
 * atm, fills *out (count 0: nothing looks like a unit mistake). */
void sf_atmosphere_unit_warnings(const sf_atmosphere *atm, const char *source, sf_unit_warnings *out);

#endif
