/* libFuzzer target: the scene file (SPEC §5, models/scene_file.h). Relative
 * paths resolve against tests/fuzz/scene_files/, which holds an atmosphere
 * file (earth.json) the seeds name. An accepted scene must also give a valid
 * domain (sf_scene_get_domain): the loader's checks imply the domain's. */
#include <stdint.h>
#include <stdlib.h>

#include "models/scene_file.h"
#include "tests/fuzz/fuzz_common.h"

#ifndef SKYFIT_FUZZ_DIR
#error "SKYFIT_FUZZ_DIR (the tests/fuzz folder) is set by cmake/SkyfitFuzz.cmake"
#endif

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  char *text = fuzz_text(data, size);
  sf_scene *scene = malloc(sizeof *scene);
  if (!text || !scene) {
    free(text);
    free(scene);
    return 0;
  }
  sf_error err = {0};
  int status = sf_scene_load_string(text, "fuzz-scene.json", SKYFIT_FUZZ_DIR "/scene_files", scene, &err);
  fuzz_require_clean(status, &err);
  if (status == SF_OK) {
    sf_scene_domain domain;
    sf_error err2 = {0};
    int status2 = sf_scene_get_domain(scene, &domain, &err2);
    if (status2 != SF_OK) fprintf(stderr, "%s\n", err2.message);
    fuzz_require(status2 == SF_OK, "an accepted scene has no valid domain");
    fuzz_require(domain.h_min_km <= domain.h_max_km && domain.mu_min <= domain.mu_max &&
                     domain.mu_s_min <= domain.mu_s_max,
                 "an accepted scene's domain is empty");
  }
  free(text);
  free(scene);
  return 0;
}
