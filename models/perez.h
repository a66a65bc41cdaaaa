/* The Perez et al. 1993 sky distribution as used by Preetham 1999 (SPEC
 * §7.2; seed 000 eq. 33; ../shared/data/preetham1999.md):
 *
 *   F(theta, gamma) = (1 + A exp(B / cos theta)) (1 + C exp(D gamma) + E cos^2 gamma)
 *
 * theta: view zenith angle (0 up, pi/2 horizon), gamma: angle between view
 * and sun, radians. No offset on cos theta (unlike Hosek). Coefficients in
 * the paper's order c[0..4] = A, B, C, D, E. */
#ifndef SKYFIT_MODELS_PEREZ_H
#define SKYFIT_MODELS_PEREZ_H

#define SF_PEREZ_N_COEFFS 5

/* F at cos theta (> 0 for a finite value when B > 0) and gamma. */
double sf_perez_f(const double c[SF_PEREZ_N_COEFFS], double cos_theta, double gamma);

/* F and its gradient d F / d c[k] (for least squares); cos_gamma must be
 * cos(gamma) (passed in so fits can precompute it). */
double sf_perez_f_grad(const double c[SF_PEREZ_N_COEFFS], double cos_theta, double gamma,
                       double cos_gamma, double grad[SF_PEREZ_N_COEFFS]);

#endif
