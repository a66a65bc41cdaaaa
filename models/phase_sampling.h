/* Importance sampling of the phase functions of models/phase.h, for the
 * path tracer. Each sampler draws nu, the cosine between the direction a
 * photon travelled before scattering and after it (forward peak at nu = 1,
 * the convention of sf_phase_value), and states the density it draws from
 * (per steradian, azimuth uniform), so that callers weight a sample by
 * sf_phase_value / sf_phase_sample_pdf. That ratio is exactly 1 (up to
 * rounding) for every kind except two: a double Henyey-Greenstein whose f is
 * outside [0, 1] (not a mixture: sampled from |1-f| HG(g1) + |f| HG(g2)), and
 * |g| < SF_PHASE_SAMPLE_TINY_G (sampled without the lobe, since the inversion
 * formula divides by g; the weight corrects it). */
#ifndef SKYFIT_MODELS_PHASE_SAMPLING_H
#define SKYFIT_MODELS_PHASE_SAMPLING_H

#include "models/atmosphere.h"
#include "models/rng.h"

#define SF_PHASE_SAMPLE_TINY_G 1e-5

/* Draws nu for phase p (SF_PHASE_NONE draws uniformly). Rayleigh: exact
 * inversion of its cubic CDF; Henyey-Greenstein: exact inversion;
 * Cornette-Shanks: Henyey-Greenstein with the same g, accepted with
 * probability (1 + nu^2) / 2 (their ratio is 3 (1 + nu^2) / (2 (2 + g^2)));
 * double Henyey-Greenstein: choose a lobe, then invert. */
double sf_phase_sample_nu(const sf_phase *p, sf_rng *rng);

/* The density (over the sphere of directions) that sf_phase_sample_nu draws
 * nu from. */
double sf_phase_sample_pdf(const sf_phase *p, double nu);

/* Henyey-Greenstein inversion for one uniform number u in [0, 1). */
double sf_phase_sample_hg_nu(double g, double u);
/* Rayleigh inversion: the root of nu^3 + 3 nu = 8 u - 4 (Cardano). */
double sf_phase_sample_rayleigh_nu(double u);

#endif
