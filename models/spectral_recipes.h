/* Named recipes that derive per-wavelength coefficients from the shipped
 * tables (SPEC §4 spectral mode). In an atmosphere file, in spectral mode
 * ("channels": {"wavelengths_nm": [...]}), "scattering", "absorption" and
 * "sun_irradiance" may be a recipe object instead of numbers:
 *
 *   {"recipe": "rayleigh_bucholtz", "scale": 1}
 *       Bucholtz 1995 standard-air beta_s (rayleigh_bucholtz.csv, 1/km),
 *       interpolated log-log (a power law between the 10 nm samples) times
 *       scale (optional, default 1: e.g. a number-density ratio).
 *   {"recipe": "rayleigh_lambda4", "reference_nm": 1000, "reference_per_km": 1.24062e-3}
 *       beta(l) = reference_per_km (reference_nm / l)^4 (seed 004 eq. 8:
 *       scattering proportional to 1/lambda^4). The values shown are
 *       Bruneton's demo (1.24062e-6 lambda_um^-4 per m), which give the
 *       default atmosphere's Rayleigh triplet at 680/550/440 nm.
 *   {"recipe": "rayleigh_formula", "refractive_index": 1.0003, "number_density_per_m3": 2.545e25}
 *       beta(l) = 8 pi^3 (n^2 - 1)^2 / (3 N l^4) (seed 002 eq. 2), in 1/km.
 *   {"recipe": "ozone_cross_section", "column_du": 300}
 *       beta_a(l) = sigma(l) N_peak, sigma from ozone_cross_section.csv (m²,
 *       the tabulated value at l, linear between; PAS demo convention: the
 *       table's value at l is the mean over the bin [l, l + 10) nm, taken
 *       at the bin's lower edge, which puts the Chappuis band 5 nm bluer
 *       than bin-centred use: sigma +6 % at 550 nm, +30 % at 440) and
 *       N_peak the number density where this constituent's density profile
 *       is 1: column_du * 2.687e20 m^-2 / (integral of the profile over
 *       altitude). For the default ozone tent (integral 15 km) and 300 DU:
 *       5.374e18 m^-3 (bruneton_demo_constants.csv).
 *   {"recipe": "angstrom", "reference_nm": 550, "reference_per_km": 4e-3, "exponent": 1.3}
 *       beta(l) = reference_per_km (l / reference_nm)^-exponent (Ångström
 *       law; exponent 0, the default, is a grey aerosol).
 *   {"recipe": "constant", "value": 3.996e-3}
 *       the same value at every wavelength (as a single number does).
 *   "sun_irradiance": {"recipe": "solar_astm_g173", "bin_nm": 5, "scale": 1}
 *       ASTM G173-03 extraterrestrial spectrum (W m^-2 nm^-1) averaged over
 *       [l - bin/2, l + bin/2] (the exact mean of the piecewise-linear
 *       table), times scale. bin_nm defaults to 5 (the reference's spacing).
 *
 * The loader replaces a recipe by the numbers it gives, so the canonical
 * JSON (and the hash) holds the derived coefficients: the hash changes when
 * a shipped table changes. Recipes are rejected in "rgb" mode. */
#ifndef SKYFIT_MODELS_SPECTRAL_RECIPES_H
#define SKYFIT_MODELS_SPECTRAL_RECIPES_H

#include "models/atmosphere.h"
#include "util/error.h"

/* 1 Dobson unit in molecules per m² (bruneton_demo_constants.csv). */
#define SF_DOBSON_UNIT_PER_M2 2.687e20

/* seed 004 eq. 8 */
double sf_rayleigh_lambda4_per_km(double lambda_nm, double reference_nm, double reference_per_km);
/* seed 002 eq. 2, in 1/km */
double sf_rayleigh_formula_per_km(double lambda_nm, double refractive_index,
                                  double number_density_per_m3);
double sf_angstrom_per_km(double lambda_nm, double reference_nm, double reference_per_km,
                          double exponent);
/* Integral of the constituent's density profile over [0, thickness] (km). */
double sf_density_column_km(const sf_constituent *c, double thickness_km);
/* Number density (1/m³) where the profile is 1, for a column in DU. */
double sf_ozone_peak_number_density(double column_du, double profile_column_km);

/* Table-based recipes at n wavelengths; SF_ERR_INPUT when a table is
 * missing or a wavelength is outside it (naming both). */
int sf_recipe_rayleigh_bucholtz(int n, const double *lambda_nm, double scale, double *out_per_km,
                                sf_error *err);
int sf_recipe_ozone_cross_section(int n, const double *lambda_nm, double peak_number_density_per_m3,
                                  double *out_per_km, sf_error *err);
int sf_recipe_solar_astm_g173(int n, const double *lambda_nm, double bin_nm, double scale,
                              double *out_w_m2_nm, sf_error *err);

#endif
