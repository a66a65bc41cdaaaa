#include "models/sigmoid_transmittance.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

double sf_sigmoid_transmittance(const double a[SF_SIGMOID_N_COEFFS], double h_km, double mu) {
  return 1.0 / (1.0 + exp(-(a[0] + a[1] * h_km + a[2] * mu + a[3] * mu * mu)));
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

void sf_sigmoid_model_eval(const sf_sigmoid_model *m, double h_km, double mu,
                           double *transmittance) {
  for (int k = 0; k < m->n_channels; ++k) {
    double t = 1.0;
    for (int c = 0; c < m->n_constituents; ++c) t *= sf_sigmoid_transmittance(m->a[c][k], h_km, mu);
    transmittance[k] = t;
  }
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
  int shape[3] = {out->n_constituents, out->n_channels, SF_SIGMOID_N_COEFFS};
  int n_values = SF_MAX_CONSTITUENTS * SF_MAX_CHANNELS * SF_SIGMOID_N_COEFFS;
  double *values = malloc(sizeof *values * (size_t)n_values);
  if (!values && status == SF_OK) status = sf_fail(err, SF_ERR_INTERNAL, "out of memory");
  if (status == SF_OK) status = sf_weights_param(&w, "a", 3, shape, values, n_values, err);
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
