/* Sigmoid-polynomial transmittance (SPEC §7.1, seed 000 §9.5): per
 * constituent c and channel k, for a viewer at altitude h (km above the
 * bottom radius) looking along mu = cos(view zenith), the transmittance of
 * the ray to its end (the ground if it hits it, else the top) is
 *
 *   T_ck(h, mu) = 1 / (1 + exp(-(a1 + a2 h + a3 mu + a4 mu^2)))
 *
 * and the total transmittance of channel k is the product over c.
 *
 * Weights file (SPEC §8, models/weights_file.h), model "sigmoid", quantity
 * "transmittance":
 *   params.a: shape [n_constituents][n_channels][4] = (a1, a2, a3, a4), in
 *             the order of the file's atmosphere constituents and channels;
 *             h in km (no input normalisation), mu unitless;
 *   domain:   the (h, mu) box the fit covers;
 *   metrics:  rmse, max_abs (of the total per channel), plus per constituent.
 * A constituent that is transparent in a channel (zero extinction) has
 * a = (40, 0, 0, 0): T = 1 to double precision. */
#ifndef SKYFIT_MODELS_SIGMOID_TRANSMITTANCE_H
#define SKYFIT_MODELS_SIGMOID_TRANSMITTANCE_H

#include "models/atmosphere.h"
#include "models/weights_file.h"
#include "util/error.h"

#define SF_SIGMOID_N_COEFFS 4
#define SF_SIGMOID_TRANSPARENT_A1 40.0

/* T for one constituent and channel. */
double sf_sigmoid_transmittance(const double a[SF_SIGMOID_N_COEFFS], double h_km, double mu);
/* T and d T / d a[k]. */
double sf_sigmoid_transmittance_grad(const double a[SF_SIGMOID_N_COEFFS], double h_km, double mu,
                                     double grad[SF_SIGMOID_N_COEFFS]);

typedef struct sf_sigmoid_model {
  int n_constituents, n_channels;
  double a[SF_MAX_CONSTITUENTS][SF_MAX_CHANNELS][SF_SIGMOID_N_COEFFS];
} sf_sigmoid_model;

/* Total transmittance per channel: the product over constituents. */
void sf_sigmoid_model_eval(const sf_sigmoid_model *m, double h_km, double mu,
                           double *transmittance);

/* Loads a weights file (models/weights_file.h validation: finite numbers,
 * atmosphere hash) and checks model "sigmoid" and the shape of params.a
 * against the file's atmosphere. w receives the file (caller frees with
 * sf_weights_free) when not NULL. SF_ERR_INPUT naming the file and key. */
int sf_sigmoid_model_load(const char *path, sf_sigmoid_model *out, sf_weights *w, sf_error *err);

#endif
