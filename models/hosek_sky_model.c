#include "models/hosek_sky_model.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "util/constants.h"

const char *sf_sky_form_model_name(sf_sky_form f) {
  return f == SF_SKY_FORM_HOSEK ? "hosek" : "preetham";
}

const char *sf_sky_form_scale_name(sf_sky_form f) {
  return f == SF_SKY_FORM_HOSEK ? "radiance" : "scale";
}

int sf_sky_form_n_coeffs(sf_sky_form f) {
  return f == SF_SKY_FORM_HOSEK ? SF_HOSEK_N_COEFFS : SF_PEREZ_N_COEFFS;
}

double sf_sky_form_f(sf_sky_form f, const double *c, double cos_theta, double gamma,
                     double cos_gamma, double *grad) {
  double scratch[SF_HOSEK_N_COEFFS];
  double *g = grad ? grad : scratch;
  return f == SF_SKY_FORM_HOSEK ? sf_hosek_f_grad(c, cos_theta, gamma, cos_gamma, g)
                                : sf_perez_f_grad(c, cos_theta, gamma, cos_gamma, g);
}

void sf_elevation_sky_state(const sf_elevation_sky_model *m, int channel, double elevation_rad,
                            double *coeffs, double *scale) {
  double x = sf_bezier_x_of_elevation(elevation_rad);
  for (int i = 0; i < m->n_coeffs; ++i)
    coeffs[i] = sf_bezier_eval(&m->coefficients[channel][0][i], SF_HOSEK_N_COEFFS, x);
  *scale = sf_bezier_eval(m->scale[channel], 1, x);
}

void sf_elevation_sky_radiance(const sf_elevation_sky_model *m, double elevation_rad,
                               double theta, double gamma, double *radiance) {
  double cos_theta = cos(theta), cos_gamma = cos(gamma);
  for (int k = 0; k < m->n_channels; ++k) {
    double c[SF_HOSEK_N_COEFFS], s;
    sf_elevation_sky_state(m, k, elevation_rad, c, &s);
    radiance[k] = s * sf_sky_form_f(m->form, c, cos_theta, gamma, cos_gamma, NULL);
  }
}

int sf_elevation_sky_add_params(cJSON *doc, const sf_elevation_sky_model *m) {
  int nk = m->n_channels, nc = m->n_coeffs;
  double *c = malloc(sizeof *c * (size_t)(nk * SF_BEZIER_POINTS * nc));
  double *s = malloc(sizeof *s * (size_t)(nk * SF_BEZIER_POINTS));
  int status = (c && s) ? 0 : -1;
  if (status == 0) {
    for (int k = 0; k < nk; ++k)
      for (int j = 0; j < SF_BEZIER_POINTS; ++j) {
        s[k * SF_BEZIER_POINTS + j] = m->scale[k][j];
        for (int i = 0; i < nc; ++i) c[(k * SF_BEZIER_POINTS + j) * nc + i] = m->coefficients[k][j][i];
      }
    int cshape[3] = {nk, SF_BEZIER_POINTS, nc}, sshape[2] = {nk, SF_BEZIER_POINTS}, rshape[1] = {2};
    double range[2] = {m->elevation_min_rad, m->elevation_max_rad};
    if (sf_weights_add_input(doc, "sun_elevation_rad", 0.0, 2.0 / SF_PI) ||
        sf_weights_add_param(doc, "coefficients", 3, cshape, c) ||
        sf_weights_add_param(doc, sf_sky_form_scale_name(m->form), 2, sshape, s) ||
        sf_weights_add_param(doc, "sun_elevation_rad", 1, rshape, range))
      status = -1;
  }
  free(c);
  free(s);
  return status;
}

int sf_elevation_sky_load(const char *path, sf_sky_form form, sf_elevation_sky_model *out,
                          sf_weights *w_out, sf_error *err) {
  memset(out, 0, sizeof *out);
  sf_weights w;
  if (sf_weights_load_file(path, sf_sky_form_model_name(form), &w, err) != SF_OK)
    return err->status;
  int status = SF_OK;
  if (strcmp(w.quantity, "sky_radiance") != 0)
    status = sf_fail(err, SF_ERR_INPUT, "%s: quantity: expected \"sky_radiance\", got \"%s\"", path,
                     w.quantity);
  static const sf_weights_input inputs[1] = {{"sun_elevation_rad", 0.0, 2.0 / SF_PI}};
  if (status == SF_OK) status = sf_weights_check_fixed_inputs(&w, inputs, 1, err);
  out->form = form;
  out->n_coeffs = sf_sky_form_n_coeffs(form);
  out->n_channels = w.atmosphere.n_channels;
  int nk = out->n_channels, nc = out->n_coeffs;
  double *c = malloc(sizeof *c * (size_t)(nk * SF_BEZIER_POINTS * nc));
  double *s = malloc(sizeof *s * (size_t)(nk * SF_BEZIER_POINTS));
  if ((!c || !s) && status == SF_OK) status = sf_fail(err, SF_ERR_INTERNAL, "out of memory");
  int cshape[3] = {nk, SF_BEZIER_POINTS, nc}, sshape[2] = {nk, SF_BEZIER_POINTS}, rshape[1] = {2};
  double range[2] = {0, 0};
  if (status == SF_OK)
    status = sf_weights_param(&w, "coefficients", 3, cshape, c, nk * SF_BEZIER_POINTS * nc, err);
  if (status == SF_OK)
    status = sf_weights_param(&w, sf_sky_form_scale_name(form), 2, sshape, s,
                              nk * SF_BEZIER_POINTS, err);
  if (status == SF_OK) status = sf_weights_param(&w, "sun_elevation_rad", 1, rshape, range, 2, err);
  if (status == SF_OK) status = sf_weights_check_params_read(&w, err);
  if (status == SF_OK && !(range[0] >= 0.0 && range[0] <= range[1] && range[1] <= 0.5 * SF_PI + 1e-12))
    status = sf_fail(err, SF_ERR_INPUT,
                     "%s: params.sun_elevation_rad: expected 0 <= min <= max <= pi/2, got [%g, %g]",
                     path, range[0], range[1]);
  if (status == SF_OK) {
    out->elevation_min_rad = range[0];
    out->elevation_max_rad = range[1];
    for (int k = 0; k < nk; ++k)
      for (int j = 0; j < SF_BEZIER_POINTS; ++j) {
        out->scale[k][j] = s[k * SF_BEZIER_POINTS + j];
        for (int i = 0; i < nc; ++i) out->coefficients[k][j][i] = c[(k * SF_BEZIER_POINTS + j) * nc + i];
      }
  }
  free(c);
  free(s);
  if (status != SF_OK || !w_out) sf_weights_free(&w);
  else *w_out = w;
  if (status != SF_OK) memset(out, 0, sizeof *out);
  return status;
}
