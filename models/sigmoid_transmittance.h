/* Sigmoid-polynomial transmittance (SPEC §7.1, seed 000 §9.5, eq. 43).
 *
 * What the sigmoid models: per constituent c and channel k, the
 * transmittance of the ray from altitude h (km above the bottom radius R)
 * along mu = cos(view zenith) to the TOP boundary (radius Rt = R + H):
 *
 *   x_ck(h, mu)     = a1 + a2 h + a3 mu + a4 mu^2
 *   T_top_ck(h, mu) = 1 / (1 + exp(-x_ck(h, mu)))                 (seed 000 §9.5)
 *   log T_top_ck    = -softplus(-x_ck),  softplus(y) = max(y, 0) + log(1 + exp(-|y|))
 *
 * fitted for rays that look up or horizontally (mu >= 0), the only rays
 * the full-ray rule below asks for (fit/fit_sigmoid.h): rays looking down
 * are reversed (seed 000 §9.6.3: the model is "not accurate enough when the
 * view ray is looking towards the planet surface, the rays are instead
 * reversed"), which keeps the steep cliff of T at the horizon out of the
 * sigmoid. Total per channel: log T_top_k = sum_c log T_top_ck.
 *
 * Full ray, sf_sigmoid_model_eval(m, h, mu) (the viewer's ray to the ground
 * if it hits it, else to the top), per channel k, with L_k = log T_top_k:
 *   1. h < 0 is taken as 0, mu clamped to [-1, 1]. A viewer above the top
 *      (h > H) is moved to where its ray enters (sf_ray_enter_from_above:
 *      from the closest approach p = r sqrt(1 - mu^2), r = R + h; if
 *      mu >= 0 or p >= Rt the ray never enters: T = 1; otherwise
 *      mu <- -sqrt((Rt - p)(Rt + p)) / Rt, h <- H).
 *   2. r = R + h, disc = (R - r)(R + r) + (r mu)^2 (the ground sphere's
 *      discriminant, cancellation-free; models/ray_geometry.h).
 *   3. mu >= 0:                          T_k = exp(L_k(h, mu)).
 *   4. mu < 0, disc < 0 (misses the ground): the ray passes its lowest
 *      point (tangent altitude h_t, zenith cosine 0) and rises to the top;
 *      by symmetry viewer->tangent has the transmittance of tangent->(the
 *      point at altitude h on the far side, looking along -mu), so
 *        h_t = -disc / (sqrt(r^2 (1 - mu^2)) + R)     (= r sqrt(1 - mu^2) - R)
 *        T_k = T_top_k(h_t, 0)^2 / T_top_k(h, -mu)
 *            = exp(min(0, 2 L_k(h_t, 0) - L_k(h, -mu))).
 *   5. mu < 0, disc >= 0 (hits the ground): eq. 43 with reversed rays: the
 *      ground point's zenith cosine is mu_g = -sqrt(disc) / R
 *      (r^2 (1 - mu^2) = R^2 (1 - mu_g^2)), both reversed rays point up:
 *        T_k = T_top_k(0, -mu_g) / T_top_k(h, -mu)
 *            = exp(min(0, L_k(0, -mu_g) - L_k(h, -mu))).
 *   The log forms avoid dividing two tiny numbers (SPEC §10); min(0, .)
 *   keeps T <= 1 where the fit is not monotone.
 * A segment of the ray, viewer to distance d (point at h_d, mu_d): without
 * a ground hit T = exp(min(0, log T_full(h, mu) - log T_full(h_d, mu_d)))
 * with log T_full from steps 3-4 at each point (same ray, same end); with a
 * ground hit T = exp(min(0, L_k(h_d, -mu_d) - L_k(h, -mu))). A segment that
 * reaches the ray's end is the whole ray (the formula would divide by the
 * fit's T_top at the exit, which is near 1 but not 1: 0.7 % off on one
 * default-scene ray).
 *
 * Weights file (SPEC §8, models/weights_file.h), model "sigmoid", quantity
 * "transmittance":
 *   params.a: shape [n_constituents][n_channels][4] = (a1, a2, a3, a4) of
 *             T_top, in the order of the file's atmosphere constituents and
 *             channels; h in km (no input normalisation), mu unitless; R and
 *             Rt are the file's atmosphere's radii;
 *   domain:   the scene's (h, mu) box;
 *   metrics:  rmse, max_abs: full rays over the domain (all channels);
 *             top_rmse, top_max_abs: the to-top rays the sigmoid was fitted
 *             on; per constituent and channel the to-top fit.
 * A constituent that is transparent in a channel (zero extinction) has
 * a = (40, 0, 0, 0): T = 1 to double precision. */
#ifndef SKYFIT_MODELS_SIGMOID_TRANSMITTANCE_H
#define SKYFIT_MODELS_SIGMOID_TRANSMITTANCE_H

#include "models/atmosphere.h"
#include "models/weights_file.h"
#include "util/error.h"

#define SF_SIGMOID_N_COEFFS 4
#define SF_SIGMOID_TRANSPARENT_A1 40.0

/* T_top for one constituent and channel. */
double sf_sigmoid_transmittance(const double a[SF_SIGMOID_N_COEFFS], double h_km, double mu);
/* T_top and d T_top / d a[k]. */
double sf_sigmoid_transmittance_grad(const double a[SF_SIGMOID_N_COEFFS], double h_km, double mu,
                                     double grad[SF_SIGMOID_N_COEFFS]);
/* log T_top = -softplus(-x), exact for large |x|. */
double sf_sigmoid_log_transmittance(const double a[SF_SIGMOID_N_COEFFS], double h_km, double mu);

typedef struct sf_sigmoid_model {
  int n_constituents, n_channels;
  double a[SF_MAX_CONSTITUENTS][SF_MAX_CHANNELS][SF_SIGMOID_N_COEFFS];
  double bottom_radius_km, top_radius_km;   /* R, Rt of the atmosphere it was fitted for */
} sf_sigmoid_model;

/* Full-ray transmittance per channel (steps 1-4 above). */
void sf_sigmoid_model_eval(const sf_sigmoid_model *m, double h_km, double mu,
                           double *transmittance);
/* Transmittance per channel of the segment from the viewer to distance
 * d_km along the ray (the ray's end at most), as the emitted
 * skyfit_sigmoid_transmittance_segment: the ratio of two full rays
 * (eq. 43), reversed for a ray that ends on the ground. */
void sf_sigmoid_model_eval_segment(const sf_sigmoid_model *m, double h_km, double mu, double d_km,
                                   double *transmittance);
/* To-top transmittance per channel, prod_c T_top_ck(h, mu), as fitted
 * (no geometry: meaningful for mu >= 0). */
void sf_sigmoid_model_eval_top(const sf_sigmoid_model *m, double h_km, double mu,
                               double *transmittance);

/* Loads a weights file (models/weights_file.h validation: finite numbers,
 * atmosphere hash) and checks model "sigmoid" and the shape of params.a
 * against the file's atmosphere; the radii come from that atmosphere.
 * w receives the file (caller frees with sf_weights_free) when not NULL.
 * SF_ERR_INPUT naming the file and key. */
int sf_sigmoid_model_load(const char *path, sf_sigmoid_model *out, sf_weights *w, sf_error *err);

#endif
