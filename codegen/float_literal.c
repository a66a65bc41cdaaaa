#include "codegen/float_literal.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int same_bits(float a, float b) { return memcmp(&a, &b, sizeof a) == 0; }

int sf_float_literal(float v, char out[SF_FLOAT_LITERAL_LEN]) {
  out[0] = '\0';
  if (!isfinite(v)) return -1;
  char digits[24];
  /* 9 significant digits always round-trip a float32 (IEEE 754 §5.12.2);
   * fewer are tried first so constants stay readable. glibc prints the
   * exactly rounded decimal, so the text is the same on every run. */
  for (int precision = 1; precision <= 9; ++precision) {
    snprintf(digits, sizeof digits, "%.*g", precision, (double)v);
    if (same_bits(strtof(digits, NULL), v)) break;
  }
  /* Moderate magnitudes read better without an exponent ("6360" rather
   * than "6.36e+03"): the shortest fixed-point text that round-trips. */
  double magnitude = fabs((double)v);
  if (strchr(digits, 'e') && magnitude >= 1e-4 && magnitude < 1e7) {
    char fixed[48];
    for (int decimals = 0; decimals <= 12; ++decimals) {
      snprintf(fixed, sizeof fixed, "%.*f", decimals, (double)v);
      if (same_bits(strtof(fixed, NULL), v)) {
        if (strlen(fixed) < sizeof digits) snprintf(digits, sizeof digits, "%s", fixed);
        break;
      }
    }
  }
  /* "3" or "-0" would be integers: give them a fraction. */
  const char *suffix = strpbrk(digits, ".e") ? "f" : ".0f";
  snprintf(out, SF_FLOAT_LITERAL_LEN, "%s%s", digits, suffix);
  return 0;
}
