/* Float constants in emitted code round-trip exactly (SPEC §9): for 2e5
 * random bit patterns (every exponent, denormals, extremes) and special
 * values, strtof of the literal (minus its 'f') gives the identical bits;
 * the literal parses as a float in C and GLSL (has '.' or 'e', ends in 'f');
 * it uses at most 9 significant digits; and no shorter %.Ng text would
 * round-trip (shortest). Non-finite values are refused. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "codegen/float_literal.h"

static int same_bits(float a, float b) { return memcmp(&a, &b, sizeof a) == 0; }

/* Digits of the mantissa without leading and trailing zeros. */
static int significant_digits(const char *s) {
  char d[40];
  int n = 0;
  for (; *s && *s != 'e' && *s != 'f'; ++s)
    if (*s >= '0' && *s <= '9' && (n > 0 || *s != '0')) d[n++] = *s;
  while (n > 0 && d[n - 1] == '0') --n;
  return n;
}

static int check_one(float v, int *shortest_failures) {
  char lit[SF_FLOAT_LITERAL_LEN];
  if (sf_float_literal(v, lit) != 0) return 0;
  size_t n = strlen(lit);
  if (n < 2 || lit[n - 1] != 'f' || !strpbrk(lit, ".e")) return 0;
  char text[SF_FLOAT_LITERAL_LEN];
  memcpy(text, lit, n - 1);
  text[n - 1] = '\0';
  if (!same_bits(strtof(text, NULL), v)) return 0;
  int digits = significant_digits(text);
  if (digits > 9) return 0;
  /* shortest: one digit fewer in %g form must not round-trip */
  if (digits > 1) {
    char shorter[40];
    int len = snprintf(shorter, sizeof shorter, "%.*g", digits - 1, (double)v);   /* at most 8 digits: fits */
    if (len > 0 && (size_t)len < sizeof shorter && same_bits(strtof(shorter, NULL), v)) ++*shortest_failures;
  }
  return 1;
}

int main(void) {
  uint64_t state = 0x9e3779b97f4a7c15ull;
  int bad = 0, not_shortest = 0, tested = 0;
  for (int i = 0; i < 200000; ++i) {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    uint32_t bits = (uint32_t)(state >> 32);
    float v;
    memcpy(&v, &bits, sizeof v);
    if (!isfinite(v)) continue;
    ++tested;
    if (!check_one(v, &not_shortest) && bad++ < 5) {
      char lit[SF_FLOAT_LITERAL_LEN];
      sf_float_literal(v, lit);
      printf("  bad literal for %a: %s\n", (double)v, lit);
    }
  }
  const float specials[] = {0.0f, -0.0f, 1.0f, -1.0f, 0.1f, 6360.0f, 3.4028235e38f, -3.4028235e38f,
                            1.17549435e-38f, 1.4e-45f, -1.4e-45f, 8.5e-05f, 1e-4f, 1e9f, 16777217.0f};
  for (size_t i = 0; i < sizeof specials / sizeof specials[0]; ++i) {
    ++tested;
    if (!check_one(specials[i], &not_shortest)) {
      ++bad;
      printf("  bad literal for special %a\n", (double)specials[i]);
    }
  }
  char lit[SF_FLOAT_LITERAL_LEN];
  CHECK(sf_float_literal(INFINITY, lit) == -1 && lit[0] == '\0');
  CHECK(sf_float_literal(NAN, lit) == -1);
  CHECK(sf_float_literal(-0.0f, lit) == 0 && strcmp(lit, "-0.0f") == 0);
  CHECK(sf_float_literal(6360.0f, lit) == 0 && strcmp(lit, "6360.0f") == 0);
  CHECK(sf_float_literal(0.1f, lit) == 0 && strcmp(lit, "0.1f") == 0);
  printf("%d values tested, %d failed to round-trip or parse, %d not shortest\n", tested, bad,
         not_shortest);
  CHECK(tested > 190000);
  CHECK(bad == 0);
  CHECK(not_shortest == 0);
  return check_summary();
}
