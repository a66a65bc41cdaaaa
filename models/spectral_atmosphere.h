/* The atmosphere of the spectral reference (SPEC §4 spectral mode, §6
 * "spectral radiance"): the scene's atmosphere at the reference wavelengths
 * (360-830 nm at 5 nm, 95 channels).
 *
 * From a spectral atmosphere: every per-channel array is interpolated
 * linearly in wavelength (exact when its wavelengths are the reference's;
 * they must cover 360-830 nm).
 * From an RGB atmosphere (channels r, g, b taken at 680/550/440 nm, the
 * wavelengths of seed 003 §6 and of Bruneton's demo), its spectral
 * counterpart:
 *  - a coefficient array with all three values > 0 becomes the power law
 *    a lambda^-alpha through them (least squares in log-log): Rayleigh's
 *    lambda^-4 triplet of the default gives alpha = 4 exactly, its grey Mie
 *    alpha = 0 (an Ångström law in general);
 *  - the absorption of a purely absorbing constituent (no scattering) whose
 *    triplet has ozone's shape (k sigma_O3 at the three wavelengths within
 *    SF_OZONE_SHAPE_TOLERANCE, relative) becomes k sigma_O3(lambda)
 *    (ozone_cross_section.csv), k the least squares fit to the three
 *    values: the default's ozone triplet is 300 DU on its tent exactly;
 *    any other absorber is a coefficient array as below;
 *  - other arrays (some zero) and the ground albedo: piecewise linear
 *    through the three values, constant beyond;
 *  - the sun: the ASTM G173 extraterrestrial spectrum averaged over each
 *    channel's 5 nm bin, scaled so that its CIE 1931 luminance Y equals the
 *    luminance of the RGB sun (Y = 0.2126 r + 0.7152 g + 0.0722 b for the
 *    shipped sRGB matrix): the spectral sky is as bright as the RGB one.
 * Densities, phase functions and radii are kept. */
#ifndef SKYFIT_MODELS_SPECTRAL_ATMOSPHERE_H
#define SKYFIT_MODELS_SPECTRAL_ATMOSPHERE_H

#include "models/atmosphere.h"
#include "models/spectral_data.h"
#include "util/error.h"

#define SF_SPECTRAL_MIN_NM 360.0
#define SF_SPECTRAL_MAX_NM 830.0
#define SF_SPECTRAL_STEP_NM 5.0
#define SF_SPECTRAL_CHANNELS 95
/* seed 003 §6 (and PAS kLambdaR/G/B) */
#define SF_RGB_LAMBDA_R_NM 680.0
#define SF_RGB_LAMBDA_G_NM 550.0
#define SF_RGB_LAMBDA_B_NM 440.0
/* How far (relative, in the 2-norm) an absorber's triplet may be from
 * ozone's cross-sections times a constant and still be taken as ozone. */
#define SF_OZONE_SHAPE_TOLERANCE 1e-2

/* The n wavelengths from min_nm to max_nm at step_nm (n <= SF_MAX_CHANNELS);
 * returns n. */
int sf_spectral_grid(double min_nm, double max_nm, double step_nm, double *lambda_nm);

/* The spectral atmosphere of src at the n wavelengths (see above). *out is
 * finalized. SF_ERR_INPUT when src's wavelengths do not cover them or a
 * table is missing. out must not alias src. */
int sf_spectral_atmosphere(const sf_atmosphere *src, int n, const double *lambda_nm, sf_atmosphere *out,
                           sf_error *err);

/* 1 for an aerosol: a constituent that scatters with a phase function other
 * than Rayleigh's (seed 003 §4.3). */
int sf_constituent_is_aerosol(const sf_constituent *c, int n_channels);
/* in without its aerosols (seed 003 §5.4.3 optimises with Rayleigh and
 * ozone only). Returns how many were removed. *out is finalized. */
int sf_atmosphere_without_aerosols(const sf_atmosphere *in, sf_atmosphere *out);

/* CIE 1931 luminance of the sun: sum over channels of ybar E dlambda with
 * dlambda the channel spacing (the atmosphere must be spectral with evenly
 * spaced wavelengths). */
double sf_spectral_sun_luminance(const sf_atmosphere *spectral, const sf_cmf *cmf);

#endif
