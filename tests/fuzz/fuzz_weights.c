/* libFuzzer target: the weights file (SPEC §8, models/weights_file.h). An
 * accepted file is also read the way the model loaders read it
 * (sf_weights_param, sf_weights_metric), which must not fail other than
 * cleanly either. */
#include <stdint.h>
#include <stdlib.h>

#include "models/weights_file.h"
#include "tests/fuzz/fuzz_common.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  char *text = fuzz_text(data, size);
  sf_weights *w = calloc(1, sizeof *w);
  if (!text || !w) {
    free(text);
    free(w);
    return 0;
  }
  sf_error err = {0};
  int status = sf_weights_load_string(text, "fuzz-weights.json", NULL, w, &err);
  fuzz_require_clean(status, &err);
  if (status == SF_OK) {
    static const char *const names[] = {"A", "scale", "w0", "missing"};
    for (int i = 0; i < 4; ++i) {
      double values[64];
      int shape2[2] = {-1, -1}, shape1[1] = {-1};
      sf_error e2 = {0}, e1 = {0}, e0 = {0};
      fuzz_require_clean(sf_weights_param(w, names[i], 2, shape2, values, 64, &e2), &e2);
      fuzz_require_clean(sf_weights_param(w, names[i], 1, shape1, values, 64, &e1), &e1);
      fuzz_require_clean(sf_weights_param(w, names[i], 0, NULL, values, 1, &e0), &e0);
    }
    (void)sf_weights_metric(w, "rmse");
  }
  sf_weights_free(w);
  free(text);
  free(w);
  return 0;
}
