/* Writes the seed inputs of the weights and table fuzzers that are binary or
 * long (tests/fuzz/corpus/weights/, tests/fuzz/corpus/table_exr/) through
 * the real writers, so the seeds are what skyfit itself produces:
 *   fuzz_make_seed_corpus CORPUS_DIR
 * Built with SKYFIT_FUZZ=ON (cmake/SkyfitFuzz.cmake); its output is kept in
 * the source tree, rerun it when a file format changes. Seeds stay tiny so
 * that the fuzzers mutate headers and structure, not bulk numbers. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "data/table.h"
#include "data/table_exr.h"
#include "models/atmosphere_file.h"
#include "models/scene_file.h"
#include "models/weights_file.h"

static int write_table(const char *dir, const char *file, const char *quantity, int n_axes,
                       const int *sizes, int n_channels, const sf_atmosphere *atm) {
  static const char *const axis_names[] = {"h_km", "mu", "mu_s", "nu"};
  static const char *const channel_names[] = {"r", "g", "b"};
  sf_table_desc d;
  memset(&d, 0, sizeof d);
  snprintf(d.quantity, sizeof d.quantity, "%s", quantity);
  snprintf(d.parameterization, sizeof d.parameterization, "bruneton");
  d.n_axes = n_axes;
  for (int k = 0; k < n_axes; ++k) {
    snprintf(d.axes[k].name, sizeof d.axes[k].name, "%s", axis_names[k]);
    snprintf(d.axes[k].mapping, sizeof d.axes[k].mapping, "linear");
    d.axes[k].size = sizes[k];
    d.axes[k].min = k == 0 ? 0.0 : -1.0;
    d.axes[k].max = k == 0 ? 100.0 : 1.0;
  }
  d.n_channels = n_channels;
  for (int c = 0; c < n_channels; ++c) snprintf(d.channel_names[c], sizeof d.channel_names[c], "%s", channel_names[c]);
  snprintf(d.content_hash, sizeof d.content_hash, "0123456789abcdef");
  char *json = sf_atmosphere_to_json(atm);
  sf_table t;
  sf_error err = {0};
  int status = json ? sf_table_init(&t, &d, json, 0, &err) : SF_ERR_INTERNAL;
  free(json);
  if (status != SF_OK) {
    fprintf(stderr, "%s: %s\n", file, err.message);
    return 1;
  }
  size_t n = sf_table_desc_points(&d) * (size_t)n_channels;
  for (size_t i = 0; i < n; ++i) t.data[i] = (float)(0.25 + 0.5 * (double)i / (double)n);
  char path[4096];
  snprintf(path, sizeof path, "%s/table_exr/%s", dir, file);
  status = sf_table_write_exr(&t, path, &err);
  if (status != SF_OK) fprintf(stderr, "%s\n", err.message);
  sf_table_free(&t);
  return status != SF_OK;
}

static int write_weights(const char *dir, const char *file, const char *model, const sf_atmosphere *atm) {
  sf_scene_domain domain = {0.0, 0.0, 0.0, 1.0, -0.2, 1.0};
  cJSON *doc = sf_weights_new(model, "sky_radiance", atm, &domain);
  if (!doc) return 1;
  const int shape_a[2] = {3, 2}, shape_s[1] = {3};
  const double a[6] = {-1.0, -0.32, 1e-3, 0.5, 2.5, -1e-300}, s[3] = {1.0, 2.0, 3.0}, w0 = 0.125;
  int bad = sf_weights_add_input(doc, "mu", 0.0, 1.0) || sf_weights_add_input(doc, "mu_s", -0.2, 0.8) ||
            sf_weights_add_param(doc, "A", 2, shape_a, a) || sf_weights_add_param(doc, "scale", 1, shape_s, s) ||
            sf_weights_add_param(doc, "w0", 0, NULL, &w0);
  cJSON *metrics = sf_weights_metrics(doc), *training = sf_weights_training(doc);
  bad = bad || !metrics || !training || !cJSON_AddNumberToObject(metrics, "rmse", 1e-3) ||
        !cJSON_AddStringToObject(metrics, "note", "seed") || !cJSON_AddNumberToObject(training, "seed", 1);
  sf_error err = {0};
  char path[4096];
  snprintf(path, sizeof path, "%s/weights/%s", dir, file);
  if (!bad && sf_weights_write(doc, path, &err) != SF_OK) {
    fprintf(stderr, "%s\n", err.message);
    bad = 1;
  }
  cJSON_Delete(doc);
  return bad;
}

int main(int argc, char **argv) {
  if (argc != 2) {
    fprintf(stderr, "usage: %s CORPUS_DIR\n", argv[0]);
    return 2;
  }
  sf_atmosphere *atm = malloc(sizeof *atm);
  if (!atm) return 1;
  sf_atmosphere_default(atm);
  const int sizes_2d[2] = {4, 3}, sizes_4d[4] = {2, 3, 2, 2}, sizes_1d[1] = {5};
  int failed = write_table(argv[1], "transmittance_2d.exr", "transmittance", 2, sizes_2d, 3, atm) ||
               write_table(argv[1], "single_4d.exr", "single_rayleigh", 4, sizes_4d, 3, atm) ||
               write_table(argv[1], "one_axis.exr", "irradiance", 1, sizes_1d, 1, atm) ||
               write_weights(argv[1], "hosek_like.json", "hosek", atm) ||
               write_weights(argv[1], "mlp_like.json", "mlp-scattering", atm);
  free(atm);
  return failed;
}
