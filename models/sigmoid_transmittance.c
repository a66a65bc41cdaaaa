#include "models/sigmoid_transmittance.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "models/ray_geometry.h"

static double poly(const double a[SF_SIGMOID_N_COEFFS], double h_km, double mu) {
  return a[0] + a[1] * h_km + a[2] * mu + a[3] * mu * mu;   /* seed 000 §9.5 */
}

double sf_sigmoid_transmittance(const double a[SF_SIGMOID_N_COEFFS], double h_km, double mu) {
  return 1.0 / (1.0 + exp(-poly(a, h_km, mu)));
}

double sf_sigmoid_transmittance_grad(const double a[SF_SIGMOID_N_COEFFS], double h_km, double mu,
                                     double grad[SF_SIGMOID_N_COEFFS]) {
  double t = sf_sigmoid_transmittance(a, h_km, mu);
  double d = t * (1.0 - t);   /* sigma' = sigma (1 - sigma) */
  grad[0] = d;
  grad[1] = d * h_km;
  grad[2] = d * mu;
  grad[3] = d * mu * mu;
  return t;
}

double sf_sigmoid_log_transmittance(const double a[SF_SIGMOID_N_COEFFS], double h_km, double mu) {
  double y = -poly(a, h_km, mu);
  return -(fmax(y, 0.0) + log1p(exp(-fabs(y))));   /* -softplus(-x) */
}

void sf_sigmoid_model_eval_top(const sf_sigmoid_model *m, double h_km, double mu,
                               double *transmittance) {
  for (int k = 0; k < m->n_channels; ++k) {
    double t = 1.0;
    for (int c = 0; c < m->n_constituents; ++c) t *= sf_sigmoid_transmittance(m->a[c][k], h_km, mu);
    transmittance[k] = t;
  }
}

static double log_top(const sf_sigmoid_model *m, int k, double h_km, double mu) {
  double s = 0.0;
  for (int c = 0; c < m->n_constituents; ++c) s += sf_sigmoid_log_transmittance(m->a[c][k], h_km, mu);
  return s;
}

/* Clamps the inputs and moves a viewer above the top to where its ray
 * enters (step 1), from the ray's closest approach (models/ray_geometry.h):
 * (Rt - r)(Rt + r) + (r mu)^2 cancels far out, and a viewer 1e13 km away
 * looking straight down had seen T_b 0.9995 for 0.659. *d_km, if given,
 * is shortened by the distance travelled. Returns 0 if the ray never
 * enters. */
static int enter(const sf_sigmoid_model *m, double *h_km, double *mu, double *d_km) {
  double R = m->bottom_radius_km, Rt = m->top_radius_km, H = Rt - R;
  if (!(*h_km > 0.0)) *h_km = 0.0;
  *mu = fmin(fmax(*mu, -1.0), 1.0);
  if (*h_km <= H) return 1;
  double t_enter, mu_e;
  if (!sf_ray_enter_from_above(R + *h_km, *mu, 0.0, 0.0, Rt, &t_enter, &mu_e, NULL)) return 0;
  *mu = fmin(fmax(mu_e, -1.0), 1.0);
  *h_km = H;
  if (d_km) *d_km -= t_enter;
  return 1;
}

static double ground_discriminant(double R, double h_km, double mu) {
  double r = R + h_km;
  return (R - r) * (R + r) + (r * mu) * (r * mu);
}

/* log T per channel of the whole ray from a viewer inside at (h, mu),
 * steps 3-5, ground saying whether the ray ends on the ground: the emitted
 * skyfit_sigmoid_log_line, which takes the branch from its caller so that
 * both ends of a segment (one line) take the same one. */
static void log_line(const sf_sigmoid_model *m, double h_km, double mu, int ground, double *l) {
  double R = m->bottom_radius_km, r = R + h_km, disc = ground_discriminant(R, h_km, mu);
  for (int k = 0; k < m->n_channels; ++k) {
    if (mu >= 0.0) {   /* step 3 */
      l[k] = log_top(m, k, h_km, mu);
    } else if (!ground) {
      /* step 4: down to the tangent point and up again, reversed */
      double h_t = fmax(-disc, 0.0) / (sqrt(r * r * ((1.0 - mu) * (1.0 + mu))) + R);
      l[k] = fmin(0.0, 2.0 * log_top(m, k, h_t, 0.0) - log_top(m, k, h_km, -mu));
    } else {
      /* step 5: eq. 43 with reversed rays (seed 000 §9.6.3), ground point back up through the viewer */
      double mu_g = -sqrt(fmax(disc, 0.0)) / R;
      l[k] = fmin(0.0, log_top(m, k, 0.0, -mu_g) - log_top(m, k, h_km, -mu));
    }
  }
}

static int ends_on_ground(const sf_sigmoid_model *m, double h_km, double mu) {
  return mu < 0.0 && ground_discriminant(m->bottom_radius_km, h_km, mu) >= 0.0;
}

void sf_sigmoid_model_eval(const sf_sigmoid_model *m, double h_km, double mu,
                           double *transmittance) {
  for (int k = 0; k < m->n_channels; ++k) transmittance[k] = 1.0;
  if (!enter(m, &h_km, &mu, NULL)) return;
  double l[SF_MAX_CHANNELS];
  log_line(m, h_km, mu, ends_on_ground(m, h_km, mu), l);
  for (int k = 0; k < m->n_channels; ++k) transmittance[k] = exp(l[k]);
}

void sf_sigmoid_model_eval_segment(const sf_sigmoid_model *m, double h_km, double mu, double d_km,
                                   double *transmittance) {
  for (int k = 0; k < m->n_channels; ++k) transmittance[k] = 1.0;
  if (!enter(m, &h_km, &mu, &d_km) || !(d_km > 0.0)) return;
  double R = m->bottom_radius_km, Rt = m->top_radius_km, r = R + h_km;
  int ground = ends_on_ground(m, h_km, mu);
  /* the segment ends at the ray's end at most: the ground or the top */
  double t_near, t_far, end = 0.0;
  if (sf_ray_sphere_intersections(r, mu, ground ? R : Rt, &t_near, &t_far)) end = fmax(ground ? t_near : t_far, 0.0);
  double la[SF_MAX_CHANNELS], lb[SF_MAX_CHANNELS];
  if (d_km >= end) {   /* the whole ray: the fit's T_top at the exit is not 1 exactly */
    log_line(m, h_km, mu, ground, la);
    for (int k = 0; k < m->n_channels; ++k) transmittance[k] = exp(la[k]);
    return;
  }
  double h_raw = sf_ray_altitude_at(R, h_km, mu, d_km);
  double h_d = fmin(fmax(h_raw, 0.0), Rt - R);
  double mu_d = fmin(fmax((r * mu + d_km) / fmax(R + h_raw, 1e-6), -1.0), 1.0);
  for (int k = 0; k < m->n_channels && ground; ++k) {   /* reversed: from the point at d back up through the viewer */
    la[k] = log_top(m, k, h_d, -mu_d);
    lb[k] = log_top(m, k, h_km, -mu);
  }
  if (!ground) {
    log_line(m, h_km, mu, 0, la);
    log_line(m, h_d, mu_d, 0, lb);
  }
  for (int k = 0; k < m->n_channels; ++k) transmittance[k] = exp(fmin(la[k] - lb[k], 0.0));
}

int sf_sigmoid_model_load(const char *path, sf_sigmoid_model *out, sf_weights *w_out,
                          sf_error *err) {
  memset(out, 0, sizeof *out);
  sf_weights w;
  if (sf_weights_load_file(path, "sigmoid", &w, err) != SF_OK) return err->status;
  int status = SF_OK;
  if (strcmp(w.quantity, "transmittance") != 0)
    status = sf_fail(err, SF_ERR_INPUT, "%s: quantity: expected \"transmittance\", got \"%s\"", path,
                     w.quantity);
  out->n_constituents = w.atmosphere.n_constituents;
  out->n_channels = w.atmosphere.n_channels;
  out->bottom_radius_km = w.atmosphere.bottom_radius_km;
  out->top_radius_km = w.atmosphere.top_radius_km;
  static const sf_weights_input inputs[2] = {{"h_km", 0.0, 1.0}, {"mu", 0.0, 1.0}};
  if (status == SF_OK) status = sf_weights_check_fixed_inputs(&w, inputs, 2, err);
  int shape[3] = {out->n_constituents, out->n_channels, SF_SIGMOID_N_COEFFS};
  int n_values = SF_MAX_CONSTITUENTS * SF_MAX_CHANNELS * SF_SIGMOID_N_COEFFS;
  double *values = malloc(sizeof *values * (size_t)n_values);
  if (!values && status == SF_OK) status = sf_fail(err, SF_ERR_INTERNAL, "out of memory");
  if (status == SF_OK) status = sf_weights_param(&w, "a", 3, shape, values, n_values, err);
  if (status == SF_OK) status = sf_weights_check_params_read(&w, err);
  if (status == SF_OK)
    for (int c = 0; c < out->n_constituents; ++c)
      for (int k = 0; k < out->n_channels; ++k)
        for (int j = 0; j < SF_SIGMOID_N_COEFFS; ++j)
          out->a[c][k][j] = values[(c * out->n_channels + k) * SF_SIGMOID_N_COEFFS + j];
  free(values);
  if (status != SF_OK || !w_out) sf_weights_free(&w);
  else *w_out = w;
  if (status != SF_OK) memset(out, 0, sizeof *out);
  return status;
}
