/* The brightness normalisation of a scattering network (models/mlp_sky.h,
 * sf_mlp_output_norm): fitted to its training set, applied to the targets
 * before training, undone for metrics.
 *
 * Why. The sky at dawn (sun 6° below the horizon) is hundreds of times
 * dimmer than at noon, and plain MSE on the raw targets spends the network
 * on the bright part: the build's network has an error the size of the image
 * in the dawn views (bench/views_scale.sh). Dividing every target by the
 * brightness of its altitude and sun elevation weighs each of them alike,
 * without the log loss's weight on values near 0 (rays of length 0, the
 * shadowed sky). A network has a fixed capacity, so this trades: the dawn
 * views' error falls 2-6x, noon's rises up to 2.4x (bench/mlp_normalise.sh,
 * the README's table); `skyfit fit mlp-scattering --normalise brightness`.
 *
 * How. The samples are grid points of the tables, so they come in slices of
 * equal (sqrt h, mu_s): one per altitude and sun elevation, spanning every
 * view direction and azimuth. A slice's brightness is the RMS of its
 * targets; b(u, v) is the least-squares polynomial (degrees A in u =
 * normalised sqrt h, C in v = normalised mu_s) through the logs of the lit
 * slices' brightnesses (those above SF_OUTPUT_NORM_FLOOR of the largest:
 * slices of rays of length 0, from the ground towards it, hold no light and
 * say nothing of it), capped at cap_below under the log of the brightest
 * slice's: slices within e^cap_below of the brightest keep their relative
 * weights as raw targets have them, and only the dimmer ones are lifted.
 * The training targets become y / exp(b); the model multiplies by exp(b). */
#ifndef SKYFIT_FIT_OUTPUT_NORM_H
#define SKYFIT_FIT_OUTPUT_NORM_H

#include "fit/dataset.h"
#include "models/mlp_sky.h"

#define SF_OUTPUT_NORM_FLOOR 1e-6
/* The largest normalised target a set may hold (targets divided by the
 * fitted brightness are about 1 on the lit slices); beyond it the set
 * stays raw (sf_output_norm_prepare). */
#define SF_OUTPUT_NORM_MAX_SCALED 1e3
/* The degrees fit mlp-scattering uses: the logs of the default scene's
 * slice brightnesses (7 orders of magnitude) are fitted to 0.1-0.3. */
#define SF_OUTPUT_NORM_DEGREE_H 3
#define SF_OUTPUT_NORM_DEGREE_MU_S 6
/* sf_output_norm_prepare lowers the degree in mu_s, down to _MIN, while
 * the fit falls more than _MAX_DIP (natural log: a factor 2) below both
 * slices either side of a point between them, checked at _DIP_STEPS - 1
 * points between each two (fit/output_norm.c: largest_dip). */
#define SF_OUTPUT_NORM_DEGREE_MU_S_MIN 2
#define SF_OUTPUT_NORM_MAX_DIP 0.6931471805599453
#define SF_OUTPUT_NORM_DIP_STEPS 16
/* The cap's default distance below the brightest slice's log brightness. */
#define SF_OUTPUT_NORM_CAP_BELOW 1.5

/* d: a scattering set (inputs sqrt h, mu, mu_s, nu normalised, any
 * targets); cap_below >= 0, or INFINITY for no cap. SF_ERR_INPUT if it has
 * fewer lit slices than coefficients, no light at all, degrees out of
 * 0..SF_MLP_NORM_MAX_DEGREE or a negative cap_below. */
int sf_output_norm_fit(const sf_dataset *d, int degree_h, int degree_mu_s, double cap_below, sf_mlp_output_norm *out,
                       sf_error *err);

/* What skyfit build and fit mlp-scattering do with a sky network's set: fit
 * with the degrees above and cap_below (a lower degree in mu_s where that
 * one dips between the slices, above), and apply. A set too coarse for them
 * (the fit's SF_ERR_INPUT, or a dip at every degree) is left raw with out
 * inactive, and why (if why_size > 0) says so, for the caller to tell the
 * user; any other error is returned. */
int sf_output_norm_prepare(sf_dataset *d, double cap_below, sf_mlp_output_norm *out, char *why, size_t why_size,
                           sf_error *err);

/* Divides d's targets by exp(b) (sf_output_norm_apply) or multiplies them
 * back (sf_output_norm_restore). */
void sf_output_norm_apply(const sf_mlp_output_norm *n, sf_dataset *d);
void sf_output_norm_restore(const sf_mlp_output_norm *n, sf_dataset *d);

#endif
