#include "models/phase_sampling.h"

#include <math.h>

#include "models/phase.h"

#define SF_PI 3.14159265358979323846

static double clamp_cosine(double nu) { return nu > 1.0 ? 1.0 : (nu < -1.0 ? -1.0 : nu); }

double sf_phase_sample_hg_nu(double g, double u) {
  if (fabs(g) < SF_PHASE_SAMPLE_TINY_G) return clamp_cosine(1.0 - 2.0 * u);
  /* Pharr, Jakob & Humphreys, PBR 3rd ed. §15.2.3, with u -> 1 - u so that
   * u = 0 gives nu = 1: nu = (1 + g^2 - s^2) / (2g), s = (1 - g^2)/(1 + g - 2gu). */
  double s = (1.0 - g * g) / (1.0 + g - 2.0 * g * u);
  return clamp_cosine((1.0 + g * g - s * s) / (2.0 * g));
}

double sf_phase_sample_rayleigh_nu(double u) {
  /* CDF of 3/8 (1 + x^2) on [-1, nu] is 3/8 (nu + nu^3/3 + 4/3) = u, i.e.
   * nu^3 + 3 nu - q = 0 with q = 8u - 4. One real root (Cardano):
   * nu = A - 1/A with A = cbrt(q/2 + sqrt(q^2/4 + 1)); A >= cbrt(sqrt(5) - 2)
   * so there is no cancellation worth fearing. */
  double z = 4.0 * u - 2.0;
  double a = cbrt(z + sqrt(z * z + 1.0));
  return clamp_cosine(a - 1.0 / a);
}

static double uniform_nu(sf_rng *rng) { return clamp_cosine(1.0 - 2.0 * sf_rng_uniform(rng)); }

/* Henyey-Greenstein as sampled: uniform when g is too small to invert. */
static double hg_pdf_as_sampled(double g, double nu) {
  return fabs(g) < SF_PHASE_SAMPLE_TINY_G ? sf_phase_isotropic()
                                          : sf_phase_henyey_greenstein(g, nu);
}

static double cornette_shanks_sample(double g, sf_rng *rng) {
  /* Acceptance (1 + nu^2)/2 >= 1/2: at most 2 tries on average. */
  for (;;) {
    double nu = sf_phase_sample_hg_nu(g, sf_rng_uniform(rng));
    if (2.0 * sf_rng_uniform(rng) < 1.0 + nu * nu) return nu;
  }
}

double sf_phase_sample_nu(const sf_phase *p, sf_rng *rng) {
  switch (p->kind) {
    case SF_PHASE_RAYLEIGH: return sf_phase_sample_rayleigh_nu(sf_rng_uniform(rng));
    case SF_PHASE_HENYEY_GREENSTEIN: return sf_phase_sample_hg_nu(p->g, sf_rng_uniform(rng));
    case SF_PHASE_CORNETTE_SHANKS: return cornette_shanks_sample(p->g, rng);
    case SF_PHASE_DOUBLE_HENYEY_GREENSTEIN: {
      double w1 = fabs(1.0 - p->f), w2 = fabs(p->f);
      double total = w1 + w2;
      double pick = sf_rng_uniform(rng) * total;
      return sf_phase_sample_hg_nu(pick < w1 ? p->g1 : p->g2, sf_rng_uniform(rng));
    }
    case SF_PHASE_ISOTROPIC:
    case SF_PHASE_NONE: break;
  }
  return uniform_nu(rng);
}

double sf_phase_sample_pdf(const sf_phase *p, double nu) {
  switch (p->kind) {
    case SF_PHASE_RAYLEIGH: return sf_phase_rayleigh(nu);
    case SF_PHASE_HENYEY_GREENSTEIN: return hg_pdf_as_sampled(p->g, nu);
    case SF_PHASE_CORNETTE_SHANKS:
      return fabs(p->g) < SF_PHASE_SAMPLE_TINY_G ? sf_phase_rayleigh(nu)
                                                 : sf_phase_cornette_shanks(p->g, nu);
    case SF_PHASE_DOUBLE_HENYEY_GREENSTEIN: {
      double w1 = fabs(1.0 - p->f), w2 = fabs(p->f);
      return (w1 * hg_pdf_as_sampled(p->g1, nu) + w2 * hg_pdf_as_sampled(p->g2, nu)) / (w1 + w2);
    }
    case SF_PHASE_ISOTROPIC:
    case SF_PHASE_NONE: break;
  }
  return 1.0 / (4.0 * SF_PI);
}
