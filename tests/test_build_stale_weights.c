/* fit/build_stale_weights.h: after a successful build, the weights files an
 * earlier run left in OUT/weights for models this run did not fit are
 * removed; only the names a build writes are touched, and never one this
 * run wrote. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "fit/build_stale_weights.h"
#include "fit/candidate_registry.h"
#include "tests/check.h"

static void plant(const char *dir, const char *name) {
  char path[512];
  snprintf(path, sizeof path, "%s/%s", dir, name);
  FILE *f = fopen(path, "w");
  if (f) {
    fputs("{}\n", f);
    fclose(f);
  }
}

static int exists(const char *dir, const char *name) {
  char path[512];
  snprintf(path, sizeof path, "%s/%s", dir, name);
  return access(path, F_OK) == 0;
}

int main(void) {
  /* Names a build writes: every registered model, restarts of the
   * networks, the 4-wavelength weights. */
  const char *build_names[] = {"sigmoid.json", "mlp-transmittance.json", "mlp-scattering.json", "preetham.json",
                               "hosek.json", "mlp-transmittance-2.json", "mlp-scattering-3.json",
                               "mlp-scattering-12.json", "spectral4.json"};
  for (size_t k = 0; k < sizeof build_names / sizeof build_names[0]; ++k) {
    int ok = sf_build_weights_name(build_names[k]);
    if (!ok) printf("not recognised: %s\n", build_names[k]);
    CHECK(ok);
  }
  /* Anything else: a user's file, a restart of a model that has none, a
   * malformed restart number, another extension, an interrupted write. */
  const char *other_names[] = {"notes.json", "hosek-2.json", "sigmoid-2.json", "mlp-scattering-0.json",
                               "mlp-scattering-02.json", "mlp-scattering-.json", "mlp-scattering-2x.json",
                               "mlp-scattering--2.json", "mlp-scattering.JSON", "mlp-scattering.json.tmp",
                               "mlp-scattering.json.tmp.42.abcdef", ".json", "mlp.json", "spectral4-2.json",
                               "xsigmoid.json", "sigmoid"};
  for (size_t k = 0; k < sizeof other_names / sizeof other_names[0]; ++k) {
    int no = !sf_build_weights_name(other_names[k]);
    if (!no) printf("taken for a build's: %s\n", other_names[k]);
    CHECK(no);
  }

  /* The networks' names (fit/candidate_registry.h), which the build's
   * restart rule measures: a network or its restart, counted to len. */
  const char *networks[] = {"mlp-transmittance", "mlp-scattering", "mlp-scattering-2", "mlp-transmittance-17"};
  for (size_t k = 0; k < sizeof networks / sizeof networks[0]; ++k)
    CHECK(sf_candidate_network_name(networks[k], strlen(networks[k])));
  const char *not_networks[] = {"sigmoid", "hosek", "preetham", "hosek-2", "mlp-scattering-02", "mlp-scattering-",
                                "mlp-scattering-0", "mlp-scattering-2x", "mlp", "naive16", "table", ""};
  for (size_t k = 0; k < sizeof not_networks / sizeof not_networks[0]; ++k)
    CHECK(!sf_candidate_network_name(not_networks[k], strlen(not_networks[k])));
  CHECK(sf_candidate_network_name("mlp-scattering-3.json", strlen("mlp-scattering-3")));
  CHECK(!sf_candidate_network_name("mlp-scattering-3", strlen("mlp-scattering-")));

  char dir[] = "/tmp/skyfit_test_stale_weights_XXXXXX";
  if (!mkdtemp(dir)) {
    perror("mkdtemp");
    return 1;
  }
  const char *planted[] = {"sigmoid.json", "mlp-scattering.json", "mlp-scattering-2.json", "mlp-scattering-3.json",
                           "hosek.json", "spectral4.json", "notes.json", "hosek-2.json", "mlp-scattering.json.tmp"};
  size_t n_planted = sizeof planted / sizeof planted[0];
  for (size_t k = 0; k < n_planted; ++k) plant(dir, planted[k]);
  /* This run wrote sigmoid, mlp-scattering and mlp-scattering-2. */
  char w0[512], w1[512], w2[512];
  snprintf(w0, sizeof w0, "%s/sigmoid.json", dir);
  snprintf(w1, sizeof w1, "%s/mlp-scattering.json", dir);
  snprintf(w2, sizeof w2, "%s/mlp-scattering-2.json", dir);
  const char *written[] = {w0, w1, w2};
  int removed = -1;
  sf_error err = {0};
  CHECK(sf_build_remove_stale_weights(dir, written, 3, &removed, &err) == SF_OK);
  CHECK(removed == 3);   /* mlp-scattering-3, hosek, spectral4 */
  const char *kept[] = {"sigmoid.json", "mlp-scattering.json", "mlp-scattering-2.json", "notes.json",
                        "hosek-2.json", "mlp-scattering.json.tmp"};
  const char *gone[] = {"mlp-scattering-3.json", "hosek.json", "spectral4.json"};
  for (size_t k = 0; k < sizeof kept / sizeof kept[0]; ++k) {
    if (!exists(dir, kept[k])) printf("removed but should stay: %s\n", kept[k]);
    CHECK(exists(dir, kept[k]));
  }
  for (size_t k = 0; k < sizeof gone / sizeof gone[0]; ++k) {
    if (exists(dir, gone[k])) printf("left but stale: %s\n", gone[k]);
    CHECK(!exists(dir, gone[k]));
  }
  /* A second pass finds nothing more. */
  CHECK(sf_build_remove_stale_weights(dir, written, 3, &removed, &err) == SF_OK && removed == 0);
  for (size_t k = 0; k < n_planted; ++k) {
    char path[512];
    snprintf(path, sizeof path, "%s/%s", dir, planted[k]);
    remove(path);
  }
  CHECK(rmdir(dir) == 0);
  /* A missing folder holds nothing stale: a build that fitted nothing
   * makes none (DIR/weights is made when a run publishes weights). */
  sf_error missing = {0};
  removed = -1;
  CHECK(sf_build_remove_stale_weights(dir, written, 3, &removed, &missing) == SF_OK && removed == 0);
  /* a path that is no folder is still an error naming it */
  char file_path[600];
  snprintf(file_path, sizeof file_path, "%s.file", dir);
  FILE *fp = fopen(file_path, "w");
  CHECK(fp != NULL);
  if (fp) fclose(fp);
  CHECK(sf_build_remove_stale_weights(file_path, written, 3, &removed, &missing) == SF_ERR_INPUT);
  CHECK(strstr(missing.message, file_path) != NULL);
  printf("not a folder: %s\n", missing.message);
  remove(file_path);
  return check_summary();
}
