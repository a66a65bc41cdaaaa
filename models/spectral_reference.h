/* The spectral reference (SPEC §6 "sky radiance ... spectral radiance
 * converted to XYZ/sRGB"): sky radiance per wavelength from the reference
 * tables of a spectral atmosphere (single scattering of every constituent
 * with its phase function + all computed orders of multiple scattering,
 * data/sky_lookup.h), and its CIE 1931 2° tristimulus values
 * X = sum_k xbar(l_k) L(l_k) dl (seed 003 eq. 5.9 as a Riemann sum on the
 * 5 nm grid of the CIE table, eq. 5.10 with uniform weights). */
#ifndef SKYFIT_MODELS_SPECTRAL_REFERENCE_H
#define SKYFIT_MODELS_SPECTRAL_REFERENCE_H

#include <stddef.h>

#include "data/sky_lookup.h"
#include "models/spectral_data.h"

/* One (viewer, view direction, sun) sample of the sky. */
typedef struct sf_view_sample {
  double h_km, mu, mu_s, nu;
  double sun_elevation_deg;
  double scale;    /* radiance multiplier: exposure (SPEC §12) x normalisation */
  double weight;   /* weight in the loss (1 for evaluation samples) */
} sf_view_sample;

/* Spectral radiance (times sample.scale) of samples [0, n) into
 * radiance[i * n_channels + ch]; in_atmosphere[i] = 0 where the ray never
 * enters the atmosphere (radiance 0). Threads: n_threads (<= 0: OpenMP's
 * default); the values do not depend on it. */
void sf_spectral_radiance(const sf_sky_tables *sky, size_t n, const sf_view_sample *samples, int n_threads,
                          double *radiance, unsigned char *in_atmosphere);

/* XYZ of a spectrum sampled at n evenly spaced wavelengths (spacing dl =
 * the grid step). */
void sf_spectrum_to_xyz(const sf_cmf *cmf, int n, const double *lambda_nm, const double *radiance, double xyz[3]);

/* Linear interpolation of a spectrum on an even grid at any wavelength
 * (clamped into the grid): the 4-wavelength fit's reading of L(lambda). */
double sf_spectrum_at(int n, const double *lambda_nm, const double *radiance, double at_nm);

#endif
