#include "util/error.h"

#include <stdarg.h>
#include <stdio.h>

int sf_fail(sf_error *err, enum sf_status status, const char *fmt, ...) {
  if (!err || err->status != SF_OK) return status;
  err->status = status;
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(err->message, sizeof err->message, fmt, ap);
  va_end(ap);
  return status;
}
