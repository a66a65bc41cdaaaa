#include "util/error.h"

#include <stdarg.h>
#include <stdio.h>
#include <string.h>

/* Messages quote what the user wrote (key names, values, file names, CSV
 * fields), which may hold newlines or other control bytes; written as
 * escapes they keep the message on the one line SPEC §4 promises (and a
 * crafted input cannot forge extra lines of output). Cut short, never
 * overflowing, when the escapes make it longer than the buffer. */
static void escape_control_bytes(char *message, size_t size) {
  char raw[sizeof ((sf_error *)0)->message];
  size_t n = strlen(message);
  if (n >= sizeof raw) n = sizeof raw - 1;
  memcpy(raw, message, n);
  raw[n] = '\0';
  size_t out = 0;
  for (size_t i = 0; i < n; ++i) {
    unsigned char ch = (unsigned char)raw[i];
    char piece[5] = {(char)ch, '\0'};
    if (ch == '\n') memcpy(piece, "\\n", 3);
    else if (ch == '\r') memcpy(piece, "\\r", 3);
    else if (ch == '\t') memcpy(piece, "\\t", 3);
    else if (ch < 0x20 || ch == 0x7f) snprintf(piece, sizeof piece, "\\x%02x", ch);
    size_t len = strlen(piece);
    if (out + len + 1 > size) break;
    memcpy(message + out, piece, len);
    out += len;
  }
  message[out] = '\0';
}

int sf_fail(sf_error *err, enum sf_status status, const char *fmt, ...) {
  if (!err || err->status != SF_OK) return status;
  err->status = status;
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(err->message, sizeof err->message, fmt, ap);
  va_end(ap);
  escape_control_bytes(err->message, sizeof err->message);
  return status;
}
