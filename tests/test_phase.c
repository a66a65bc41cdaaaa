/* Phase functions (models/phase.h): normalisation over the sphere and mean
 * cosine against closed forms, by an independent long-double composite
 * Gauss-Legendre rule on a mesh graded geometrically towards nu = -1 and
 * nu = +1 (the forward peak of HG at g = 0.99 has width ~(1-g)^2/(2g) =
 * 5e-5 in nu, so pieces of size 2^-k resolve it); special cases; dispatch. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "check.h"
#include "independent_integrals.h"
#include "models/phase.h"
#include "util/constants.h"

#define GL_N 20
typedef struct gauss_legendre {
  ld x[GL_N], w[GL_N];
} gauss_legendre;

static gauss_legendre gl_make(void) {
  gauss_legendre q;
  ind_gauss_legendre(GL_N, q.x, q.w);
  return q;
}

typedef double (*phase_fn)(const void *ctx, double nu);

/* 2 pi * integral over [-1, 1] of nu^power p(nu), on pieces with breakpoints
 * 0, +-(1 - 2^-k) for k = 1..60. */
static ld sphere_integral(const gauss_legendre *q, phase_fn p, const void *ctx, int power) {
  ld breaks[2 * 61 + 1];
  int n = 0;
  breaks[n++] = -1;
  for (int k = 60; k >= 1; --k) breaks[n++] = -1 + ldexpl(1, -k);
  breaks[n++] = 0;
  for (int k = 1; k <= 60; ++k) breaks[n++] = 1 - ldexpl(1, -k);
  breaks[n++] = 1;
  ld sum = 0;
  for (int i = 0; i + 1 < n; ++i) {
    ld a = breaks[i], b = breaks[i + 1], c = 0.5L * (a + b), hw = 0.5L * (b - a), piece = 0;
    for (int j = 0; j < GL_N; ++j) {
      ld nu = c + hw * q->x[j];
      piece += q->w[j] * (ld)p(ctx, (double)nu) * (power ? nu : 1);
    }
    sum += hw * piece;
  }
  return 2 * 3.14159265358979323846264338327950288L * sum;
}

static double via_dispatch(const void *ctx, double nu) { return sf_phase_value((const sf_phase *)ctx, nu); }

static sf_phase phase_of(sf_phase_kind kind, double g, double g1, double g2, double f) {
  sf_phase p;
  memset(&p, 0, sizeof p);
  p.kind = kind;
  p.g = g;
  p.g1 = g1;
  p.g2 = g2;
  p.f = f;
  return p;
}

static void check_integrals(const gauss_legendre *q, const char *name, sf_phase p, double mean_cosine) {
  char label[128];
  snprintf(label, sizeof label, "%s: 2pi int p", name);
  ld norm = sphere_integral(q, via_dispatch, &p, 0);
  ld mean = sphere_integral(q, via_dispatch, &p, 1);
  int ok = fabsl(norm - 1) <= 1e-9L;
  printf("%s %-52s got %.17Lg want 1 abs.err %.3Lg (bound 1e-9)\n", ok ? "ok  " : "FAIL", label, norm,
         fabsl(norm - 1));
  check_report(ok, label, __FILE__, __LINE__);
  snprintf(label, sizeof label, "%s: 2pi int nu p", name);
  ok = fabsl(mean - mean_cosine) <= 1e-9L;
  printf("%s %-52s got %.17Lg want %.17g abs.err %.3Lg (bound 1e-9)\n", ok ? "ok  " : "FAIL", label, mean,
         mean_cosine, fabsl(mean - mean_cosine));
  check_report(ok, label, __FILE__, __LINE__);
}

/* Mean cosine of Cornette-Shanks, p ~ (1 + nu^2) HG(g): with the HG moments
 * <P_l> = g^l, i.e. <nu> = g, <nu^2> = (1 + 2g^2)/3, <nu^3> = (3g + 2g^3)/5,
 * (<nu> + <nu^3>) / (1 + <nu^2>) = 3 g (4 + g^2) / (5 (2 + g^2)). */
static double cornette_shanks_mean_cosine(double g) { return 3 * g * (4 + g * g) / (5 * (2 + g * g)); }

int main(void) {
  gauss_legendre q = gl_make();
  ld wsum = 0;
  for (int i = 0; i < GL_N; ++i) wsum += q.w[i];
  printf("-- Gauss-Legendre %d: weights sum to %.19Lg\n", GL_N, wsum);
  CHECK_ABS((double)wsum, 2.0, 1e-17);

  const double gs[] = {-0.9, -0.5, 0.0, 0.3, 0.8, 0.95, 0.99};
  const int n_g = (int)(sizeof gs / sizeof gs[0]);
  char name[96];

  printf("-- normalisation and mean cosine\n");
  check_integrals(&q, "rayleigh", phase_of(SF_PHASE_RAYLEIGH, 0, 0, 0, 0), 0.0);
  check_integrals(&q, "isotropic", phase_of(SF_PHASE_ISOTROPIC, 0, 0, 0, 0), 0.0);
  for (int i = 0; i < n_g; ++i) {
    snprintf(name, sizeof name, "henyey_greenstein g=%g", gs[i]);
    check_integrals(&q, name, phase_of(SF_PHASE_HENYEY_GREENSTEIN, gs[i], 0, 0, 0), gs[i]);
  }
  for (int i = 0; i < n_g; ++i) {
    snprintf(name, sizeof name, "cornette_shanks g=%g", gs[i]);
    check_integrals(&q, name, phase_of(SF_PHASE_CORNETTE_SHANKS, gs[i], 0, 0, 0),
                    cornette_shanks_mean_cosine(gs[i]));
  }
  const double dhg[][3] = {{0.8, -0.3, 0.2}, {0.99, -0.9, 0.5}, {0.3, 0.95, 0.9}, {-0.5, 0.0, 1.0}, {0.5, 0.5, 0.4}};
  for (int i = 0; i < 5; ++i) {
    double g1 = dhg[i][0], g2 = dhg[i][1], f = dhg[i][2];
    snprintf(name, sizeof name, "double_hg g1=%g g2=%g f=%g", g1, g2, f);
    check_integrals(&q, name, phase_of(SF_PHASE_DOUBLE_HENYEY_GREENSTEIN, 0, g1, g2, f),
                    (1 - f) * g1 + f * g2);
  }

  printf("-- special cases\n");
  const double nus[] = {-1.0, -0.6, 0.0, 0.25, 0.9, 1.0};
  int hg_iso = 1, dhg_hg = 1;
  double cs_rayleigh = 0;
  for (int i = 0; i < 6; ++i) {
    double nu = nus[i];
    hg_iso &= sf_phase_henyey_greenstein(0.0, nu) == sf_phase_isotropic();
    dhg_hg &= sf_phase_double_henyey_greenstein(0.8, -0.4, 0.0, nu) == sf_phase_henyey_greenstein(0.8, nu);
    double d = fabs(sf_phase_cornette_shanks(0.0, nu) - sf_phase_rayleigh(nu)) / sf_phase_rayleigh(nu);
    cs_rayleigh = d > cs_rayleigh ? d : cs_rayleigh;
  }
  printf("   HG(g=0) == isotropic bit for bit at 6 nu: %d; DHG(f=0) == HG(g1): %d\n", hg_iso, dhg_hg);
  CHECK(hg_iso);
  CHECK(dhg_hg);
  /* 3/(8pi)(1+nu^2)/2 and 3/(16pi)(1+nu^2) round differently: a few ulps */
  CHECK_ABS(cs_rayleigh, 0.0, 4 * 2.220446049250313e-16);
  CHECK_REL(sf_phase_isotropic(), 1.0 / (4.0 * SF_PI), 2.3e-16);
  CHECK_REL(sf_phase_rayleigh(1.0), 3.0 / (8.0 * SF_PI), 4.5e-16);
  /* HG forward peak: (1 - g^2)/(4 pi (1 - g)^3) = (1 + g)/(4 pi (1 - g)^2) */
  CHECK_REL(sf_phase_henyey_greenstein(0.99, 1.0), 1.99 / (4.0 * SF_PI * 0.01 * 0.01), 1e-12);
  CHECK_REL(sf_phase_henyey_greenstein(0.99, -1.0), 0.01 / (4.0 * SF_PI * 1.99 * 1.99), 1e-12);

  printf("-- sf_phase_value dispatches on the kind\n");
  const double nu = 0.37;
  sf_phase p = phase_of(SF_PHASE_RAYLEIGH, 0, 0, 0, 0);
  CHECK(sf_phase_value(&p, nu) == sf_phase_rayleigh(nu));
  p = phase_of(SF_PHASE_ISOTROPIC, 0.5, 0, 0, 0);
  CHECK(sf_phase_value(&p, nu) == sf_phase_isotropic());
  p = phase_of(SF_PHASE_HENYEY_GREENSTEIN, 0.7, 0, 0, 0);
  CHECK(sf_phase_value(&p, nu) == sf_phase_henyey_greenstein(0.7, nu));
  CHECK(sf_phase_value(&p, nu) != sf_phase_henyey_greenstein(0.6, nu));
  p = phase_of(SF_PHASE_CORNETTE_SHANKS, 0.7, 0, 0, 0);
  CHECK(sf_phase_value(&p, nu) == sf_phase_cornette_shanks(0.7, nu));
  p = phase_of(SF_PHASE_DOUBLE_HENYEY_GREENSTEIN, 0.7, 0.9, -0.2, 0.3);
  CHECK(sf_phase_value(&p, nu) == sf_phase_double_henyey_greenstein(0.9, -0.2, 0.3, nu));
  p = phase_of(SF_PHASE_NONE, 0.7, 0.9, -0.2, 0.3);
  CHECK(sf_phase_value(&p, nu) == 0.0);
  printf("   values at nu=%g: rayleigh %.17g HG(0.7) %.17g CS(0.7) %.17g DHG %.17g\n", nu,
         sf_phase_rayleigh(nu), sf_phase_henyey_greenstein(0.7, nu), sf_phase_cornette_shanks(0.7, nu),
         sf_phase_double_henyey_greenstein(0.9, -0.2, 0.3, nu));
  CHECK(strcmp(sf_phase_kind_name(SF_PHASE_CORNETTE_SHANKS), "cornette_shanks") == 0);
  CHECK(strcmp(sf_phase_kind_name(SF_PHASE_DOUBLE_HENYEY_GREENSTEIN), "double_henyey_greenstein") == 0);
  CHECK(sf_phase_kind_name(SF_PHASE_NONE) == NULL);
  return check_summary();
}
