#include "models/hosek_dataset.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cjson/cJSON.h>

#include "util/constants.h"
#include "util/data_path.h"
#include "util/json_read.h"

/* Reads a nested array of exactly the given shape into out (row-major). */
static int read_nested(const sf_json_ctx *c, const cJSON *v, const char *path, const int *shape,
                       int n_dims, double *out, int *written) {
  if (n_dims == 0) {
    if (sf_json_read_finite(c, v, path, &out[*written]) != SF_OK) return SF_ERR_INPUT;
    ++*written;
    return SF_OK;
  }
  if (!cJSON_IsArray(v) || cJSON_GetArraySize(v) != shape[0])
    return sf_json_fail(c, path, "expected an array of %d entries, got %s", shape[0],
                        cJSON_IsArray(v) ? "an array of another length" : sf_json_type_name(v));
  int i = 0;
  const cJSON *item;
  cJSON_ArrayForEach(item, v) {
    char sub[SF_JSON_PATH_LEN];
    sf_json_join_index(sub, sizeof sub, path, i++);
    if (read_nested(c, item, sub, shape + 1, n_dims - 1, out, written) != SF_OK)
      return SF_ERR_INPUT;
  }
  return SF_OK;
}

int sf_hosek_dataset_load_file(const char *path, sf_hosek_dataset *out, sf_error *err) {
  memset(out, 0, sizeof *out);
  sf_json_file_rules rules = {"Hosek dataset file", "", (size_t)16 << 20};
  char *text = NULL;
  if (sf_json_read_file(path, &rules, &text, err) != SF_OK) return err->status;
  sf_json_ctx c = {path, err};
  cJSON *root = NULL;
  int status = sf_json_parse(&c, text, &root);
  free(text);
  if (status != SF_OK) return status;
  const cJSON *channels = sf_json_get(root, "channels");
  if (!cJSON_IsArray(channels) || cJSON_GetArraySize(channels) != SF_HOSEK_DATASET_CHANNELS) {
    status = sf_json_fail(&c, "channels", "expected an array of 3 channel names");
  } else {
    for (int ch = 0; ch < SF_HOSEK_DATASET_CHANNELS && status == SF_OK; ++ch) {
      const cJSON *n = cJSON_GetArrayItem(channels, ch);
      if (!cJSON_IsString(n)) status = sf_json_fail(&c, "channels", "expected strings");
      else snprintf(out->channel_names[ch], sizeof out->channel_names[ch], "%s", n->valuestring);
    }
  }
  static const int coeff_shape[5] = {SF_HOSEK_DATASET_CHANNELS, SF_HOSEK_DATASET_ALBEDOS,
                                     SF_HOSEK_DATASET_TURBIDITIES, 6, SF_HOSEK_N_COEFFS};
  static const int radiance_shape[4] = {SF_HOSEK_DATASET_CHANNELS, SF_HOSEK_DATASET_ALBEDOS,
                                        SF_HOSEK_DATASET_TURBIDITIES, 6};
  int n = 0;
  if (status == SF_OK)
    status = read_nested(&c, sf_json_get(root, "coefficients"), "coefficients", coeff_shape, 5,
                         &out->coefficients[0][0][0][0][0], &n);
  n = 0;
  if (status == SF_OK)
    status = read_nested(&c, sf_json_get(root, "radiances"), "radiances", radiance_shape, 4,
                         &out->radiances[0][0][0][0], &n);
  cJSON_Delete(root);
  if (status != SF_OK) memset(out, 0, sizeof *out);
  return status;
}

int sf_hosek_dataset_load_default(sf_hosek_dataset *out, sf_error *err) {
  char path[4096];
  if (sf_data_file_path(SF_HOSEK_DATA_FILE, path, sizeof path, err) != SF_OK) return err->status;
  return sf_hosek_dataset_load_file(path, out, err);
}

/* The published Bezier sum, term by term as arhosekskymodel_cookconfiguration
 * writes it (pow calls included), so our state matches the reference. */
static double published_bezier(const double *p, int stride, double x) {
  return pow(1.0 - x, 5.0) * p[0] + 5.0 * pow(1.0 - x, 4.0) * x * p[stride] +
         10.0 * pow(1.0 - x, 3.0) * pow(x, 2.0) * p[2 * stride] +
         10.0 * pow(1.0 - x, 2.0) * pow(x, 3.0) * p[3 * stride] +
         5.0 * (1.0 - x) * pow(x, 4.0) * p[4 * stride] + pow(x, 5.0) * p[5 * stride];
}

/* hosek2012.md step 3: albedo-0/1 at turbidity n, then at n + 1. */
static double published_blend(const double *albedo0_t, const double *albedo1_t, int t_stride,
                              int stride, int int_turbidity, double turbidity_rem, double albedo,
                              double x) {
  const double *a0 = albedo0_t + (int_turbidity - 1) * t_stride;
  const double *a1 = albedo1_t + (int_turbidity - 1) * t_stride;
  double v = (1.0 - albedo) * (1.0 - turbidity_rem) * published_bezier(a0, stride, x);
  v += albedo * (1.0 - turbidity_rem) * published_bezier(a1, stride, x);
  if (int_turbidity == SF_HOSEK_DATASET_TURBIDITIES) return v;
  v += (1.0 - albedo) * turbidity_rem * published_bezier(a0 + t_stride, stride, x);
  v += albedo * turbidity_rem * published_bezier(a1 + t_stride, stride, x);
  return v;
}

int sf_hosek_dataset_state(const sf_hosek_dataset *d, int channel, double turbidity,
                           double albedo, double elevation_rad,
                           double coeffs[SF_HOSEK_N_COEFFS], double *radiance, sf_error *err) {
  if (channel < 0 || channel >= SF_HOSEK_DATASET_CHANNELS)
    return sf_fail(err, SF_ERR_INPUT, "Hosek dataset: channel %d outside 0..2", channel);
  if (!(turbidity >= 1.0 && turbidity <= 10.0))
    return sf_fail(err, SF_ERR_INPUT, "Hosek dataset: turbidity %g outside [1, 10]", turbidity);
  if (!(albedo >= 0.0 && albedo <= 1.0))
    return sf_fail(err, SF_ERR_INPUT, "Hosek dataset: albedo %g outside [0, 1]", albedo);
  if (!(elevation_rad >= 0.0 && elevation_rad <= 0.5 * SF_PI))
    return sf_fail(err, SF_ERR_INPUT, "Hosek dataset: sun elevation %g rad outside [0, pi/2]",
                   elevation_rad);
  int int_turbidity = (int)turbidity;
  double turbidity_rem = turbidity - (double)int_turbidity;
  double x = pow(elevation_rad / (SF_PI / 2.0), 1.0 / 3.0);
  double stored[SF_HOSEK_N_COEFFS];
  for (int k = 0; k < SF_HOSEK_N_COEFFS; ++k)
    stored[k] = published_blend(&d->coefficients[channel][0][0][0][k],
                                &d->coefficients[channel][1][0][0][k], 6 * SF_HOSEK_N_COEFFS,
                                SF_HOSEK_N_COEFFS, int_turbidity, turbidity_rem, albedo, x);
  /* storage k = 7 is I, k = 8 is H (hosek2012.md "Coefficient order") */
  for (int k = 0; k < 7; ++k) coeffs[k] = stored[k];
  coeffs[SF_HOSEK_H] = stored[8];
  coeffs[SF_HOSEK_I] = stored[7];
  *radiance = published_blend(&d->radiances[channel][0][0][0], &d->radiances[channel][1][0][0], 6,
                              1, int_turbidity, turbidity_rem, albedo, x);
  return SF_OK;
}

int sf_hosek_dataset_control_points(const sf_hosek_dataset *d, int channel, double turbidity, double albedo,
                                    double coeffs[6][SF_HOSEK_N_COEFFS], double radiance[6], sf_error *err) {
  double c[SF_HOSEK_N_COEFFS], r;
  /* the same checks (any elevation in range) */
  int status = sf_hosek_dataset_state(d, channel, turbidity, albedo, 0.0, c, &r, err);
  if (status != SF_OK) return status;
  int n = (int)turbidity;
  double rem = turbidity - (double)n;
  /* published_blend's weights, applied to each control point: the Bezier
   * is linear in its points */
  double w[4] = {(1.0 - albedo) * (1.0 - rem), albedo * (1.0 - rem), (1.0 - albedo) * rem, albedo * rem};
  int last = n == SF_HOSEK_DATASET_TURBIDITIES;
  for (int j = 0; j < 6; ++j) {
    double stored[SF_HOSEK_N_COEFFS + 1];
    for (int k = 0; k <= SF_HOSEK_N_COEFFS; ++k) {   /* k = 9: the radiance */
      int coefficient = k < SF_HOSEK_N_COEFFS;
      const double *a0 = coefficient ? &d->coefficients[channel][0][n - 1][j][k] : &d->radiances[channel][0][n - 1][j];
      const double *a1 = coefficient ? &d->coefficients[channel][1][n - 1][j][k] : &d->radiances[channel][1][n - 1][j];
      long t_stride = coefficient ? 6 * SF_HOSEK_N_COEFFS : 6;
      double v = w[0] * a0[0] + w[1] * a1[0];
      if (!last) v += w[2] * a0[t_stride] + w[3] * a1[t_stride];
      stored[k] = v;
    }
    /* storage k = 7 is I, k = 8 is H */
    for (int k = 0; k < 7; ++k) coeffs[j][k] = stored[k];
    coeffs[j][SF_HOSEK_H] = stored[8];
    coeffs[j][SF_HOSEK_I] = stored[7];
    radiance[j] = stored[SF_HOSEK_N_COEFFS];
  }
  return SF_OK;
}

double sf_hosek_dataset_radiance(const double coeffs[SF_HOSEK_N_COEFFS], double radiance_scale,
                                 double theta, double gamma) {
  return sf_hosek_f(coeffs, cos(theta), gamma) * radiance_scale;
}
