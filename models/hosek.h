/* The Hosek-Wilkie 2012 sky distribution (SPEC §7.2; seed 000 eq. 35-37;
 * ../shared/data/hosek2012.md), coefficients in the PAPER's order
 * c[0..8] = A, B, C, D, E, F, G, H, I:
 *
 *   chi(H, gamma)   = (1 + cos^2 gamma) / (1 + H^2 - 2 H cos gamma)^(3/2)
 *   F(theta, gamma) = (1 + A exp(B / (cos theta + 0.01)))
 *                     (C + D exp(E gamma) + F cos^2 gamma + G chi(H, gamma)
 *                      + I sqrt(cos theta))
 *   L = F(theta, gamma) R        (R: the channel's radiance scale)
 *
 * The exponent 3/2 of chi is that of the published code and data note (seed
 * 000 eq. 36 prints it without). The published data store H and I swapped
 * (storage k = 7 is I, k = 8 is H): models/hosek_dataset.h swaps them on
 * load, so everything here is in paper order. theta in [0, pi/2]. */
#ifndef SKYFIT_MODELS_HOSEK_H
#define SKYFIT_MODELS_HOSEK_H

#define SF_HOSEK_N_COEFFS 9

/* Index of each coefficient in paper order. */
enum { SF_HOSEK_A, SF_HOSEK_B, SF_HOSEK_C, SF_HOSEK_D, SF_HOSEK_E,
       SF_HOSEK_F, SF_HOSEK_G, SF_HOSEK_H, SF_HOSEK_I };

/* chi(g, gamma) of the Mie-like aureole term. */
double sf_hosek_chi(double g, double cos_gamma);

/* F(theta, gamma) (without the radiance scale). */
double sf_hosek_f(const double c[SF_HOSEK_N_COEFFS], double cos_theta, double gamma);

/* F and d F / d c[k]; cos_gamma = cos(gamma). */
double sf_hosek_f_grad(const double c[SF_HOSEK_N_COEFFS], double cos_theta, double gamma,
                       double cos_gamma, double grad[SF_HOSEK_N_COEFFS]);

#endif
