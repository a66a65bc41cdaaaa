/* The weights file (SPEC §8): a written file reads back bit-exactly, and
 * every class of bad file is refused with a message naming the key. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "models/atmosphere_file.h"
#include "models/weights_file.h"
#include "tests/check.h"

static cJSON *sample_doc(const sf_atmosphere *atm) {
  sf_scene_domain d = {0.0, 15.0, -1.0, 1.0, -0.17364817766693033, 1.0};
  cJSON *doc = sf_weights_new("sigmoid", "transmittance", atm, &d);
  sf_weights_add_input(doc, "h_km", 0.0, 1.0 / 15.0);
  sf_weights_add_input(doc, "mu", 0.0, 1.0);
  /* Values that need 17 digits, a denormal and a negative zero. */
  double w[2][3] = {{0.1, 1.0 / 3.0, 5e-324}, {-2.5, 6.02214076e23, -0.0}};
  int shape[2] = {2, 3};
  sf_weights_add_param(doc, "w", 2, shape, &w[0][0]);
  double bias = 0.7;
  sf_weights_add_param(doc, "bias", 0, NULL, &bias);
  cJSON_AddNumberToObject(sf_weights_metrics(doc), "rmse", 1.25e-4);
  cJSON_AddStringToObject(sf_weights_metrics(doc), "worst_at", "h=0 mu=-0.1");
  cJSON_AddNumberToObject(sf_weights_training(doc), "seed", 7);
  return doc;
}

/* Loads text expecting failure; checks the message names the key. */
static void expect_refused(const char *text, const char *key_in_message) {
  sf_weights w;
  sf_error err = {0};
  int rc = sf_weights_load_string(text, "bad.json", NULL, &w, &err);
  int ok = rc == SF_ERR_INPUT && strstr(err.message, "bad.json") && strstr(err.message, key_in_message);
  printf("%s refused (rc %d): %s\n", ok ? "ok  " : "FAIL", rc, err.message);
  CHECK(ok);
  sf_weights_free(&w);
}

/* The sample document with one substring replaced. */
static char *edited(const char *text, const char *from, const char *to) {
  const char *at = strstr(text, from);
  if (!at) {
    printf("FAIL: '%s' not in the sample text\n", from);
    CHECK(0);
    return NULL;
  }
  size_t n = strlen(text) - strlen(from) + strlen(to) + 1;
  char *out = malloc(n);
  snprintf(out, n, "%.*s%s%s", (int)(at - text), text, to, at + strlen(from));
  return out;
}

int main(void) {
  sf_atmosphere *atm = malloc(sizeof *atm);
  sf_atmosphere_default(atm);
  cJSON *doc = sample_doc(atm);
  char *text = sf_weights_print(doc);
  CHECK(text != NULL);

  /* Round trip: every value back bit for bit. */
  sf_weights *w = malloc(sizeof *w);
  sf_error err = {0};
  CHECK(sf_weights_load_string(text, "good.json", "sigmoid", w, &err) == SF_OK);
  if (err.status) printf("unexpected: %s\n", err.message);
  double v[6] = {0};
  int shape[2] = {2, -1};
  CHECK(sf_weights_param(w, "w", 2, shape, v, 6, &err) == SF_OK);
  CHECK(shape[1] == 3);
  const double want[6] = {0.1, 1.0 / 3.0, 5e-324, -2.5, 6.02214076e23, -0.0};
  int exact = 1;
  for (int i = 0; i < 6; ++i) exact &= memcmp(&v[i], &want[i], sizeof(double)) == 0 || (v[i] == 0 && want[i] == 0);
  CHECK(exact);
  double bias = 0;
  CHECK(sf_weights_param(w, "bias", 0, NULL, &bias, 1, &err) == SF_OK && bias == 0.7);
  CHECK(w->n_inputs == 2 && w->inputs[1].scale == 1.0 && fabs(w->inputs[0].scale - 1.0 / 15.0) == 0.0);
  CHECK(w->domain.h_max_km == 15.0 && w->domain.mu_s_min == -0.17364817766693033);
  CHECK(sf_weights_metric(w, "rmse") == 1.25e-4);
  CHECK(isnan(sf_weights_metric(w, "worst_at")));
  CHECK(sf_atmosphere_hash(&w->atmosphere) == sf_atmosphere_hash(atm));
  CHECK(strcmp(w->model, "sigmoid") == 0 && strcmp(w->quantity, "transmittance") == 0);

  /* A wrong shape is named with both shapes. */
  sf_error shape_err = {0};
  int want_shape[2] = {3, 2};
  CHECK(sf_weights_param(w, "w", 2, want_shape, v, 6, &shape_err) == SF_ERR_INPUT);
  printf("shape message: %s\n", shape_err.message);
  CHECK(strstr(shape_err.message, "params.w") && strstr(shape_err.message, "3x2") && strstr(shape_err.message, "2x3"));
  sf_error missing_err = {0};
  CHECK(sf_weights_param(w, "nope", 0, NULL, v, 6, &missing_err) == SF_ERR_INPUT);
  CHECK(strstr(missing_err.message, "params.nope") != NULL);
  sf_weights_free(w);

  /* The wrong model is refused. */
  sf_error model_err = {0};
  CHECK(sf_weights_load_string(text, "good.json", "hosek", w, &model_err) == SF_ERR_INPUT);
  CHECK(strstr(model_err.message, "model") != NULL);

  /* Determinism of the printed text. */
  cJSON *doc2 = sample_doc(atm);
  char *text2 = sf_weights_print(doc2);
  CHECK(strcmp(text, text2) == 0);

  /* Doubles whose 15-digit form reads back within one DBL_EPSILON but not
   * exactly (cJSON's own printer keeps 15 digits for those): 0.1 + 0.2
   * prints as 0.3 there. An atmosphere with every coefficient x1e-3 has
   * such values; its hash must survive the file. */
  {
    sf_atmosphere *thin = malloc(sizeof *thin);
    *thin = *atm;
    for (int k = 0; k < thin->n_constituents; ++k)
      for (int c = 0; c < thin->n_channels; ++c) {
        thin->constituents[k].scattering[c] *= 1e-3;
        thin->constituents[k].absorption[c] *= 1e-3;
      }
    cJSON *tdoc = sample_doc(thin);
    double near_three_tenths = 0.1 + 0.2;
    sf_weights_add_param(tdoc, "near", 0, NULL, &near_three_tenths);
    char *ttext = sf_weights_print(tdoc);
    sf_error terr = {0};
    CHECK(ttext && sf_weights_load_string(ttext, "thin.json", "sigmoid", w, &terr) == SF_OK);
    if (terr.status) printf("thin atmosphere: %s\n", terr.message);
    double back = 0.0;
    CHECK(sf_weights_param(w, "near", 0, NULL, &back, 1, &terr) == SF_OK);
    printf("0.1 + 0.2 = %.17g written, %.17g read back\n", near_three_tenths, back);
    CHECK(back == near_three_tenths);
    CHECK(sf_atmosphere_hash(&w->atmosphere) == sf_atmosphere_hash(thin));
    sf_weights_free(w);
    free(ttext);
    cJSON_Delete(tdoc);
    free(thin);
  }

  /* Bad files, one class each. */
  char *bad;
  struct { const char *from, *to, *key; } cases[] = {
      {"\"skyfit_weights\":\t1", "\"skyfit_weights\":\t2", "skyfit_weights"},
      {"\"model\":\t\"sigmoid\"", "\"model\":\t7", "model"},
      /* a sigmoid gives transmittance */
      {"\"quantity\":\t\"transmittance\"", "\"quantity\":\t\"sky_radiance\"", "quantity"},
      {"\"rmse\":\t0.000125", "\"rmse\":\t1e999", "metrics.rmse"},
      {"[0.1, ", "[NaN, ", "line"},
      {"[0.1, ", "[\"x\", ", "params.w[0][0]"},
      {"[-2.5, 6.02214076e+23, -0]", "[-2.5, 6.02214076e+23]", "params.w[1]"},
      {"\"bias\":\t0.7", "\"bias\":\t[]", "params.bias"},
      /* beyond float32, which the emitted code holds */
      {"[-2.5, 6.02214076e+23, -0]", "[-2.5, 6.02214076e+39, -0]", "params.w[1][1]"},
      {"\"h_km\":\t[0, 15]", "\"h_km\":\t[15, 0]", "domain.h_km"},
      {"\"mu\":\t[-1, 1]", "\"mu\":\t[-1, 2]", "domain.mu"},
      {"\"scale\":\t1\n", "\"scale\":\t0\n", "inputs[1].scale"},
      /* an input's normalisation is emitted too (codegen had failed naming neither) */
      {"\"scale\":\t1\n", "\"scale\":\t1e300\n", "inputs[1].scale"},
      {"\"training\"", "\"trainnig\"", "trainnig"},
      {"\"ground_albedo\":\t[0, 0, 0]", "\"ground_albedo\":\t[0, 0, 0.5]", "atmosphere_hash"},
      {"\"bottom_radius_km\":\t6360", "\"bottom_radius_km\":\t-1", "atmosphere"},
  };
  for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
    bad = edited(text, cases[i].from, cases[i].to);
    if (bad) expect_refused(bad, cases[i].key);
    free(bad);
  }
  expect_refused("[1, 2]", "object");
  expect_refused("{\"skyfit_weights\": 1}", "model");

  /* A model whose inputs are not learnt (sigmoid, Perez, Hosek) refuses a
   * file declaring another normalisation than its own; absent inputs, or
   * its own, pass. The sample declares h_km scaled 1/15. */
  {
    static const sf_weights_input sigmoid_inputs[2] = {{"h_km", 0.0, 1.0}, {"mu", 0.0, 1.0}};
    static const sf_weights_input scaled_inputs[2] = {{"h_km", 0.0, 1.0 / 15.0}, {"mu", 0.0, 1.0}};
    sf_weights fixed;
    sf_error load_err = {0}, fixed_err = {0}, own_err = {0}, names_err = {0};
    CHECK(sf_weights_load_string(text, "fixed.json", NULL, &fixed, &load_err) == SF_OK);
    int rc = sf_weights_check_fixed_inputs(&fixed, sigmoid_inputs, 2, &fixed_err);
    printf("fixed inputs: %s\n", fixed_err.message);
    CHECK(rc == SF_ERR_INPUT && strstr(fixed_err.message, "fixed.json") && strstr(fixed_err.message, "inputs[0]"));
    CHECK(sf_weights_check_fixed_inputs(&fixed, scaled_inputs, 2, &own_err) == SF_OK);
    CHECK(sf_weights_check_fixed_inputs(&fixed, scaled_inputs, 1, &names_err) == SF_ERR_INPUT);
    fixed.n_inputs = 0;
    CHECK(sf_weights_check_fixed_inputs(&fixed, sigmoid_inputs, 2, &own_err) == SF_OK);
    sf_weights_free(&fixed);
  }

  /* Writing refuses a NaN parameter (cJSON would print it as null). */
  double nan_value = NAN;
  CHECK(sf_weights_add_param(doc2, "bad", 0, NULL, &nan_value) != SF_OK);
  cJSON_AddNumberToObject(sf_weights_metrics(doc2), "broken", NAN);
  sf_error write_err = {0};
  CHECK(sf_weights_write(doc2, "/nonexistent-folder/x.json", &write_err) != SF_OK);
  CHECK(strstr(write_err.message, "non-finite") != NULL);

  free(text);
  free(text2);
  cJSON_Delete(doc);
  cJSON_Delete(doc2);
  free(w);
  free(atm);
  return check_summary();
}
