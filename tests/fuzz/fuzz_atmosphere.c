/* libFuzzer target: the atmosphere file (SPEC §4, models/atmosphere_file.h).
 * Any text is accepted or rejected cleanly (fuzz_common.h); an accepted one
 * must round-trip: its canonical JSON loads again to the same atmosphere
 * (same canonical text, same hash), as atmosphere_file.h promises. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "models/atmosphere_file.h"
#include "tests/fuzz/fuzz_common.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  char *text = fuzz_text(data, size);
  sf_atmosphere *atm = malloc(sizeof *atm), *again = malloc(sizeof *again);
  if (!text || !atm || !again) {
    free(text);
    free(atm);
    free(again);
    return 0;
  }
  sf_error err = {0};
  int status = sf_atmosphere_load_string(text, "fuzz.json", atm, &err);
  fuzz_require_clean(status, &err);
  if (status == SF_OK) {
    char *canonical = sf_atmosphere_to_json(atm);
    fuzz_require(canonical != NULL, "canonical JSON of a loaded atmosphere");
    sf_error err2 = {0};
    int status2 = sf_atmosphere_load_string(canonical, "canonical.json", again, &err2);
    if (status2 != SF_OK) fprintf(stderr, "%s\n---\n%s\n", err2.message, canonical);
    fuzz_require(status2 == SF_OK, "the canonical JSON of an accepted atmosphere is rejected");
    char *canonical2 = sf_atmosphere_to_json(again);
    fuzz_require(canonical2 && strcmp(canonical, canonical2) == 0, "canonical JSON does not round-trip");
    fuzz_require(sf_atmosphere_hash(atm) == sf_atmosphere_hash(again), "hash changes on reload");
    free(canonical2);
    free(canonical);
  }
  free(text);
  free(atm);
  free(again);
  return 0;
}
