/* printf-style appending to a fixed buffer, for the report's sentences. */
#ifndef SKYFIT_UTIL_STR_APPEND_H
#define SKYFIT_UTIL_STR_APPEND_H

#include <stddef.h>

/* Appends the formatted text to the string in buf (n bytes in all),
 * truncated to fit; buf stays terminated. */
void sf_str_append(char *buf, size_t n, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;

#endif
