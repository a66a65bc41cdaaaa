/* Minimal test harness: every check prints what it compared, so a test's
 * log states its numbers; main returns check_summary(). */
#ifndef SKYFIT_TESTS_CHECK_H
#define SKYFIT_TESTS_CHECK_H

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

static int check_passed_count = 0, check_failed_count = 0;

static inline int check_report(int ok, const char *what, const char *file, int line) {
  if (ok) ++check_passed_count;
  else {
    ++check_failed_count;
    printf("FAILED %s:%d: %s\n", file, line, what);
  }
  return ok;
}

#define CHECK(cond) check_report(!!(cond), #cond, __FILE__, __LINE__)

/* |got - want| <= rel * |want| (or <= rel when want is 0). */
#define CHECK_REL(got, want, rel)                                              \
  do {                                                                         \
    double g_ = (got), w_ = (want), r_ = (rel);                                \
    double e_ = fabs(g_ - w_) / (w_ != 0.0 ? fabs(w_) : 1.0);                  \
    int ok_ = isfinite(g_) && e_ <= r_;                                        \
    printf("%s %-48s got %.17g want %.17g rel.err %.3g (bound %.3g)\n",       \
           ok_ ? "ok  " : "FAIL", #got, g_, w_, e_, r_);                       \
    check_report(ok_, #got " vs " #want, __FILE__, __LINE__);                  \
  } while (0)

#define CHECK_ABS(got, want, tol)                                              \
  do {                                                                         \
    double g_ = (got), w_ = (want), t_ = (tol);                                \
    double e_ = fabs(g_ - w_);                                                 \
    int ok_ = isfinite(g_) && e_ <= t_;                                        \
    printf("%s %-48s got %.17g want %.17g abs.err %.3g (bound %.3g)\n",       \
           ok_ ? "ok  " : "FAIL", #got, g_, w_, e_, t_);                       \
    check_report(ok_, #got " vs " #want, __FILE__, __LINE__);                  \
  } while (0)

/* The larger of a running worst error and e, where a NaN wins and stays:
 * fmax would drop it (fmax(0, NaN) is 0), and a NaN error must fail the
 * bound checked on the worst. */
static inline double worst_of(double worst, double e) { return isnan(worst) || e <= worst ? worst : e; }

static inline int check_summary(void) {
  printf("%d passed, %d failed\n", check_passed_count, check_failed_count);
  return check_failed_count == 0 ? 0 : 1;
}

#endif
