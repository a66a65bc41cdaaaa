/* The shipped spectral tables (data/physical/, see ../shared/data/README.md)
 * and the ways to read a value at any wavelength:
 *   cie1931_2deg_5nm.csv   CIE 1931 2° colour matching functions, 360-830/5 nm
 *   rayleigh_bucholtz.csv  Bucholtz 1995 Rayleigh beta_s of standard air, 1/km
 *   ozone_cross_section.csv  O3 cross-section, m² (10 nm bins, PAS convention)
 *   astm_g173.csv          ASTM G173-03 solar spectrum (column "etr")
 * A spectrum is one column of a CSV file over its "lambda_nm" column. */
#ifndef SKYFIT_MODELS_SPECTRAL_DATA_H
#define SKYFIT_MODELS_SPECTRAL_DATA_H

#include "util/error.h"

#define SF_SPECTRUM_MAX_POINTS 2048

/* Samples of one quantity at strictly increasing wavelengths. */
typedef struct sf_spectrum {
  int n;
  double lambda_nm[SF_SPECTRUM_MAX_POINTS];
  double value[SF_SPECTRUM_MAX_POINTS];
} sf_spectrum;

/* Column `column` of data file `file_name` (found with sf_data_file_path)
 * against its lambda_nm column. SF_ERR_INPUT naming the file, line and
 * problem for a missing file or column, a bad number or non-increasing
 * wavelengths. */
int sf_spectrum_load(const char *file_name, const char *column, sf_spectrum *out, sf_error *err);

/* 1 if lambda lies in [first, last] sample. */
int sf_spectrum_covers(const sf_spectrum *s, double lambda_nm);
/* Linear interpolation (the value at a sample is exact); outside the range:
 * NAN (check sf_spectrum_covers first). */
double sf_spectrum_linear(const sf_spectrum *s, double lambda_nm);
/* Interpolation linear in log(lambda), log(value): exact for a power law
 * between samples (Rayleigh ~ lambda^-4.08); values must be > 0. */
double sf_spectrum_loglog(const sf_spectrum *s, double lambda_nm);
/* Mean over [lo, hi] of the piecewise-linear spectrum (exact integral of the
 * interpolant / (hi - lo)); the window must lie inside the range. */
double sf_spectrum_window_mean(const sf_spectrum *s, double lo_nm, double hi_nm);

/* The three CIE 1931 2° colour matching functions. */
typedef struct sf_cmf {
  sf_spectrum x, y, z;
} sf_cmf;
int sf_cmf_load(sf_cmf *out, sf_error *err);
/* xbar, ybar, zbar at lambda, linear between the 5 nm samples, 0 outside
 * 360-830 nm (the table's ends are already ~1e-4 of the peak). */
void sf_cmf_at(const sf_cmf *cmf, double lambda_nm, double xyz_bar[3]);

/* The 4-wavelength model's conversion matrices (seed 003 eq. 5.12; the
 * spectral4 weights format, fit/spectral4_run.h), row-major 3 x 4:
 * to_xyz[c][i] = cmf_c(l_i) w_i, and to_linear_srgb = M_srgb . to_xyz
 * (models/color_space.h). */
void sf_spectral4_to_xyz(const sf_cmf *cmf, const double lambda_nm[4], const double weight_nm[4],
                         double to_xyz[12]);
void sf_spectral4_srgb_of_xyz(const double to_xyz[12], double to_linear_srgb[12]);

#endif
