#include "cli/size_pair_option.h"

/* Digits from *p (at least one, at most 9: no overflow), advancing *p. */
static int digits(const char **p, long *out) {
  long v = 0;
  int n = 0;
  for (; **p >= '0' && **p <= '9'; ++*p, ++n) {
    if (n == 9) return -1;
    v = 10 * v + (**p - '0');
  }
  *out = v;
  return n > 0 ? 0 : -1;
}

int sf_cli_parse_size_pair(const char *text, int lo, int hi, int *a, int *b) {
  const char *p = text;
  long x, y;
  if (digits(&p, &x) || *p++ != 'x' || digits(&p, &y) || *p != '\0') return -1;
  if (x < lo || x > hi || y < lo || y > hi) return -1;
  *a = (int)x;
  *b = (int)y;
  return 0;
}
