#include "util/str_append.h"

#include <stdarg.h>
#include <stdio.h>
#include <string.h>

void sf_str_append(char *buf, size_t n, const char *fmt, ...) {
  size_t len = strlen(buf);
  if (len + 1 >= n) return;
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(buf + len, n - len, fmt, ap);
  va_end(ap);
}
