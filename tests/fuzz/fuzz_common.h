/* Shared by the libFuzzer targets tests/fuzz/fuzz_*.c (cmake/SkyfitFuzz.cmake)
 * and the regression test tests/test_fuzz_regressions.c: how raw bytes
 * become a loader's input, and what a loader must do with any input — accept
 * it, or reject it as bad input (SF_ERR_INPUT) with a message. Anything else
 * (a crash, a sanitizer report, SF_ERR_INTERNAL, a silent failure) is a bug,
 * and fuzz_require aborts so that libFuzzer saves the input. */
#ifndef SKYFIT_TESTS_FUZZ_COMMON_H
#define SKYFIT_TESTS_FUZZ_COMMON_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "util/error.h"

/* The bytes as a NUL-terminated string (malloc'd; NULL when out of memory).
 * A NUL inside ends the text early, as it would for a C caller. */
static inline char *fuzz_text(const uint8_t *data, size_t size) {
  char *text = malloc(size + 1);
  if (!text) return NULL;
  if (size) memcpy(text, data, size);
  text[size] = '\0';
  return text;
}

/* Aborts (a finding for libFuzzer) when cond is false. */
#define fuzz_require(cond, what)                                                  \
  do {                                                                            \
    if (!(cond)) {                                                                \
      fprintf(stderr, "fuzz invariant broken at %s:%d: %s\n", __FILE__, __LINE__, \
              (what));                                                            \
      abort();                                                                    \
    }                                                                             \
  } while (0)

/* A loader's answer is clean: success with no error recorded, or
 * SF_ERR_INPUT with a one-line message. */
static inline void fuzz_require_clean(int status, const sf_error *err) {
  if (status == SF_OK) {
    fuzz_require(err->status == SF_OK, "success but an error was recorded");
    return;
  }
  if (status != SF_ERR_INPUT || err->status != SF_ERR_INPUT || err->message[0] == '\0' ||
      strchr(err->message, '\n') != NULL)
    fprintf(stderr, "status %d, error status %d, message:\n%s\n", status, (int)err->status,
            err->message);
  fuzz_require(status == SF_ERR_INPUT && err->status == SF_ERR_INPUT,
               "a failure that is not SF_ERR_INPUT");
  fuzz_require(err->message[0] != '\0', "SF_ERR_INPUT without a message");
  fuzz_require(strchr(err->message, '\n') == NULL, "a message of more than one line");
}

#endif
