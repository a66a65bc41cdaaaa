/* Phase-function importance sampling (models/phase_sampling.h): each
 * sampler's stated density integrates to 1 and equals the phase function
 * where the sampler is exact, and the drawn cosines follow that density
 * (chi-square over 40 bins, first two moments against quadrature). */
#include <math.h>
#include <stdio.h>

#include "models/phase.h"
#include "models/phase_sampling.h"
#include "models/rng.h"
#include "tests/check.h"

#define PI 3.14159265358979323846
#define BINS 40

static const double gl8_x[8] = {-0.9602898564975363, -0.7966664774136267, -0.5255324099163290,
                                -0.1834346424956498, 0.1834346424956498,  0.5255324099163290,
                                0.7966664774136267,  0.9602898564975363};
static const double gl8_w[8] = {0.1012285362903763, 0.2223810344533745, 0.3137066458778873,
                                0.3626837833783620, 0.3626837833783620, 0.3137066458778873,
                                0.2223810344533745, 0.1012285362903763};

/* 2 pi * integral over [a, b] of pdf(nu) nu^power, composite Gauss-Legendre. */
static double pdf_moment(const sf_phase *p, double a, double b, int power) {
  const int panels = 400;
  double sum = 0.0;
  for (int k = 0; k < panels; ++k) {
    double pa = a + (b - a) * k / panels, pb = a + (b - a) * (k + 1) / panels;
    for (int j = 0; j < 8; ++j) {
      double nu = 0.5 * (pa + pb) + 0.5 * (pb - pa) * gl8_x[j];
      sum += 0.5 * (pb - pa) * gl8_w[j] * sf_phase_sample_pdf(p, nu) * pow(nu, power);
    }
  }
  return 2.0 * PI * sum;
}

static void check_kind(const char *name, sf_phase p, int exact, unsigned long long seed) {
  printf("-- %s\n", name);
  CHECK_REL(pdf_moment(&p, -1.0, 1.0, 0), 1.0, 1e-10);
  double worst = 0.0;
  for (int i = 0; i <= 2000; ++i) {
    double nu = -1.0 + 2.0 * i / 2000.0;
    double ratio = sf_phase_value(&p, nu) / sf_phase_sample_pdf(&p, nu);
    if (fabs(ratio - 1.0) > worst) worst = fabs(ratio - 1.0);
  }
  printf("   max |phase/pdf - 1| = %.3g\n", worst);
  CHECK(worst <= (exact ? 1e-13 : 1e-4));

  const long n = 400000;
  sf_rng rng;
  sf_rng_seed(&rng, seed, 1, 2);
  long counts[BINS] = {0};
  double s1 = 0.0, s2 = 0.0, s3 = 0.0, s4 = 0.0;
  for (long i = 0; i < n; ++i) {
    double nu = sf_phase_sample_nu(&p, &rng);
    int b = (int)((nu + 1.0) * 0.5 * BINS);
    if (b >= BINS) b = BINS - 1;
    if (b < 0) b = 0;
    ++counts[b];
    s1 += nu; s2 += nu * nu; s3 += nu * nu * nu; s4 += nu * nu * nu * nu;
  }
  double chi2 = 0.0;
  for (int b = 0; b < BINS; ++b) {
    double expect = n * pdf_moment(&p, -1.0 + 2.0 * b / BINS, -1.0 + 2.0 * (b + 1) / BINS, 0);
    chi2 += (counts[b] - expect) * (counts[b] - expect) / expect;
  }
  /* 39 degrees of freedom: mean 39, sd 8.8; 39 + 5 sd */
  printf("   chi-square over %d bins: %.1f (bound 83)\n", BINS, chi2);
  CHECK(chi2 < 83.0);
  double m1 = s1 / n, m2 = s2 / n;
  double se1 = sqrt((m2 - m1 * m1) / n), se2 = sqrt((s4 / n - m2 * m2) / n);
  (void)s3;
  CHECK_ABS(m1, pdf_moment(&p, -1.0, 1.0, 1), 4.0 * se1);
  CHECK_ABS(m2, pdf_moment(&p, -1.0, 1.0, 2), 4.0 * se2);
}

int main(void) {
  sf_phase p = {0};
  p.kind = SF_PHASE_RAYLEIGH;
  check_kind("rayleigh", p, 1, 1);
  /* Rayleigh's closed forms: <nu> = 0, <nu^2> = 2/5 */
  CHECK_ABS(pdf_moment(&p, -1.0, 1.0, 2), 0.4, 1e-12);
  /* the Cardano inversion hits the ends and the middle exactly */
  CHECK_ABS(sf_phase_sample_rayleigh_nu(0.0), -1.0, 1e-15);
  CHECK_ABS(sf_phase_sample_rayleigh_nu(0.5), 0.0, 1e-15);
  CHECK_ABS(sf_phase_sample_rayleigh_nu(1.0 - 1e-16), 1.0, 1e-12);
  p.kind = SF_PHASE_ISOTROPIC;
  check_kind("isotropic", p, 1, 2);
  p.kind = SF_PHASE_HENYEY_GREENSTEIN;
  p.g = 0.8;
  check_kind("henyey_greenstein g=0.8", p, 1, 3);
  CHECK_ABS(pdf_moment(&p, -1.0, 1.0, 1), 0.8, 1e-10);    /* <nu> = g */
  p.g = -0.3;
  check_kind("henyey_greenstein g=-0.3", p, 1, 4);
  CHECK_ABS(pdf_moment(&p, -1.0, 1.0, 1), -0.3, 1e-10);
  p.g = 3e-6;   /* below SF_PHASE_SAMPLE_TINY_G: drawn uniformly, weight corrects */
  check_kind("henyey_greenstein g=3e-6", p, 0, 5);
  p.kind = SF_PHASE_CORNETTE_SHANKS;
  p.g = 0.8;
  check_kind("cornette_shanks g=0.8", p, 1, 6);
  /* <nu> = 3 g (4 + g^2) / (5 (2 + g^2)) for Cornette-Shanks */
  CHECK_ABS(pdf_moment(&p, -1.0, 1.0, 1), 3.0 * 0.8 * 4.64 / (5.0 * 2.64), 1e-10);
  p.g = -0.5;
  check_kind("cornette_shanks g=-0.5", p, 1, 7);
  p.kind = SF_PHASE_DOUBLE_HENYEY_GREENSTEIN;
  p.g1 = 0.8;
  p.g2 = -0.3;
  p.f = 0.3;
  check_kind("double_henyey_greenstein 0.8/-0.3/0.3", p, 1, 8);
  /* <nu> of the mixture: (1 - f) g1 + f g2 */
  CHECK_ABS(pdf_moment(&p, -1.0, 1.0, 1), 0.7 * 0.8 + 0.3 * -0.3, 1e-10);
  return check_summary();
}
