/* Our fitted ground-level sky models (SPEC §7.2): a Perez (model
 * "preetham") or Hosek (model "hosek") distribution per channel whose
 * coefficients and radiance scale follow the sun elevation the way Hosek &
 * Wilkie's dataset does: a quintic Bezier in x = (elevation/(pi/2))^(1/3)
 * with 6 control points each (models/hosek_bezier.h). Valid for a viewer on
 * the ground (h = 0), view above the horizon, sun up (SPEC §5).
 *
 * Evaluation, channel k, sun elevation e (radians), view zenith theta and
 * view-sun angle gamma (radians):
 *   x      = (clamp(e, 0, pi/2) / (pi/2))^(1/3)
 *   w_j    = C(5,j) (1-x)^(5-j) x^j,  C(5,j) = 1 5 10 10 5 1
 *   c_i    = sum_j w_j coefficients[k][j][i]
 *   S      = sum_j w_j scale[k][j]          ("radiance" for hosek)
 *   hosek:    L = S (1 + c0 exp(c1/(cos theta + 0.01)))
 *                   (c2 + c3 exp(c4 gamma) + c5 cos^2 gamma
 *                    + c6 (1 + cos^2 gamma)/(1 + c7^2 - 2 c7 cos gamma)^(3/2)
 *                    + c8 sqrt(cos theta))            (models/hosek.h, A..I)
 *   preetham: L = S (1 + c0 exp(c1/cos theta)) (1 + c2 exp(c3 gamma) + c4 cos^2 gamma)
 *                                                     (models/perez.h, A..E)
 * L is the sky radiance of the reference (single + multiple scattering,
 * phase functions applied, the atmosphere's sun irradiance; no sun disc).
 *
 * Weights file (SPEC §8), quantity "sky_radiance":
 *   model "hosek":    params.coefficients [n_channels][6][9] (paper order A..I),
 *                     params.radiance     [n_channels][6];
 *   model "preetham": params.coefficients [n_channels][6][5] (A..E),
 *                     params.scale        [n_channels][6];
 *   both:             params.sun_elevation_rad [2]: the sun range fitted;
 *   inputs: sun_elevation_rad (offset 0, scale 2/pi, then the cube root);
 *   metrics: rmse (absolute), rel_rmse, max_abs over the fit samples, the
 *   published baselines' rmse on the same samples, and per-start results. */
#ifndef SKYFIT_MODELS_HOSEK_SKY_MODEL_H
#define SKYFIT_MODELS_HOSEK_SKY_MODEL_H

#include "models/atmosphere.h"
#include "models/hosek.h"
#include "models/hosek_bezier.h"
#include "models/perez.h"
#include "models/weights_file.h"
#include "util/error.h"

typedef enum sf_sky_form { SF_SKY_FORM_PEREZ = 0, SF_SKY_FORM_HOSEK = 1 } sf_sky_form;

typedef struct sf_elevation_sky_model {
  sf_sky_form form;
  int n_coeffs;      /* 5 (Perez) or 9 (Hosek) */
  int n_channels;
  double coefficients[SF_MAX_CHANNELS][SF_BEZIER_POINTS][SF_HOSEK_N_COEFFS];
  double scale[SF_MAX_CHANNELS][SF_BEZIER_POINTS];
  double elevation_min_rad, elevation_max_rad;
} sf_elevation_sky_model;

/* "preetham" / "hosek": the weights file's model name; the scale param's
 * name ("scale" / "radiance"). */
const char *sf_sky_form_model_name(sf_sky_form f);
const char *sf_sky_form_scale_name(sf_sky_form f);
int sf_sky_form_n_coeffs(sf_sky_form f);

/* F of the form at (cos theta, gamma); grad (may be NULL) = d F / d c. */
double sf_sky_form_f(sf_sky_form f, const double *c, double cos_theta, double gamma,
                     double cos_gamma, double *grad);

/* Coefficients and scale of channel k at a sun elevation. */
void sf_elevation_sky_state(const sf_elevation_sky_model *m, int channel, double elevation_rad,
                            double *coeffs, double *scale);
/* Radiance of every channel. */
void sf_elevation_sky_radiance(const sf_elevation_sky_model *m, double elevation_rad,
                               double theta, double gamma, double *radiance);

/* Adds params (coefficients, scale/radiance, sun_elevation_rad) and the
 * input normalisation to a weights document. */
int sf_elevation_sky_add_params(cJSON *doc, const sf_elevation_sky_model *m);

/* Loads a weights file of model "preetham" or "hosek" (form), validating
 * names and shapes against the file's atmosphere (n_channels) and the
 * elevation range (within [0, pi/2], min <= max). w receives the file
 * (caller frees) when not NULL. */
int sf_elevation_sky_load(const char *path, sf_sky_form form, sf_elevation_sky_model *out,
                          sf_weights *w, sf_error *err);

#endif
