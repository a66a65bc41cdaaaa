/* The forward and backward peaks of a phase function that the multiple
 * scattering's directions (data/precompute_multiple.h: 32 azimuths, 11.25
 * deg apart) cannot resolve, so that the tables can say so. A
 * Henyey-Greenstein lobe of g 0.99 is 0.7 deg wide: the scattering
 * density's normalised sum then takes the radiance of the nearest
 * direction, and a g-0.99 haze's sky came out 6-21x brighter than a Monte
 * Carlo path tracer's (an audit's figures), creating energy.
 *
 * The measure: the mass of the phase function above its value on the edge
 * of a cone of SF_PHASE_PEAK_CONE_DEG about the forward (backward)
 * direction, the part a delta-truncation (Wiscombe 1977, "The delta-M
 * method") would scatter exactly along the axis. Held at that level, the
 * rest is resolved by the directions about as well as Earth's Mie
 * (Cornette-Shanks, g 0.8) is whole: quadrature sums of the held g-0.99 lobe
 * 0.93-1.11, of Earth's Mie 0.91-1.05 (1 when resolved; a scratch sum over
 * 20,000 random directions), so a peak of more than
 * SF_PHASE_PEAK_MIN_FRACTION (Earth's Mie: 0.128; Henyey-Greenstein 0.85:
 * 0.21) is one the directions miss. (The truncation itself was tried: the
 * mass scattered along the axis took the previous order's radiance there,
 * whose table had smeared the sun's aureole along nu, and the orders grew
 * instead of converging.) */
#ifndef SKYFIT_DATA_PHASE_PEAK_H
#define SKYFIT_DATA_PHASE_PEAK_H

#include <stddef.h>

#include "models/atmosphere.h"

#define SF_PHASE_PEAK_CONE_DEG 12.0
#define SF_PHASE_PEAK_MIN_FRACTION 0.15

typedef struct sf_phase_peak {
  int active;        /* fraction > SF_PHASE_PEAK_MIN_FRACTION: unresolved */
  double cos_cone;   /* |cos| above which a direction lies in the cone */
  double level;      /* the phase function on the cone's edge, held inside it */
  double fraction;   /* integral over the cone of max(p - level, 0): scattered along the axis */
} sf_phase_peak;

/* The forward cone (about nu = 1) and the backward one (nu = -1) of p. */
void sf_phase_peaks(const sf_phase *p, sf_phase_peak *forward, sf_phase_peak *backward);

/* Whether some scattering constituent of atm has a peak the multiple
 * scattering does not resolve; if so, says which and how much in text (at
 * most n bytes), for the user and the report. */
int sf_phase_peaks_note(const sf_atmosphere *atm, char *text, size_t n);

#endif
