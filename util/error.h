/* Error reports that travel by explicit pointer: the first failure wins, and
 * the caller decides the exit code (SPEC §11: 2 bad input, 1 internal). */
#ifndef SKYFIT_UTIL_ERROR_H
#define SKYFIT_UTIL_ERROR_H

enum sf_status { SF_OK = 0, SF_ERR_INTERNAL = 1, SF_ERR_INPUT = 2 };

typedef struct sf_error {
  enum sf_status status;
  char message[1024];
} sf_error;

/* Records status and a printf-style message unless an error is already set.
 * The message is one line: control bytes in it (a newline in a quoted key or
 * field) are stored as escapes (\n, \t, \x01).
 * Returns status so callers can write `return sf_fail(err, ...)`. */
int sf_fail(sf_error *err, enum sf_status status, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;

static inline void sf_error_clear(sf_error *err) {
  if (err) { err->status = SF_OK; err->message[0] = '\0'; }
}

#endif
