/* A cheap estimate of how much sunlit air a view ray holds: for each
 * scattering constituent c,
 *   F_c = integral over the sunlit parts of the ray of
 *         T_view(t) rho_c(t) T_sun(t) dt,
 * with the planet's shadow cut out exactly (models/sun_shadow.h: the ray is
 * split where the sun ray grazes the ground and where the sun crosses the
 * point's horizon, and a part whose midpoint the planet hides is left
 * out; a ray that falls to a lowest point above the ground is split there
 * too), T_sun and T_view from the transmittance table (T_view as a ratio
 * of rays to the top that rise or run level, Bruneton 2017
 * GetTransmittance; with Leenman's tables, whose linear mu cannot follow T
 * near the horizontal, from the reference optical depth, data/sunlit_ray.c)
 * and an 8-point Gauss-Legendre rule on each part: the
 * single scattering (seed 000's integral, without the sun's irradiance,
 * the scattering coefficient and the phase) on a coarse rule.
 *
 * In the planet's shadow at altitude the single scattering of a fixed view
 * falls by decades within one mu_s sample (1.4 deg) and ends at a sun
 * depression, depending jointly on mu_s and nu, past which no sunlit air
 * is left on the ray (20 km, zenith: 2.0e-5 at -7.3 deg, 4.4e-6 at -8,
 * 6.9e-7 at -8.65, 0 beyond -10.1); no interpolation of the table's
 * samples follows that. F does, so the table's single scattering divided
 * by F varies slowly and interpolates well (data/sky_lookup.c), and F is
 * exactly 0 where the ray holds no sunlit air. */
#ifndef SKYFIT_DATA_SUNLIT_RAY_H
#define SKYFIT_DATA_SUNLIT_RAY_H

#include "data/table.h"
#include "data/table_params.h"
#include "models/atmosphere.h"

/* out[k][ch]: F of constituents[k] (k < n) for the table's view ray at c
 * (to the ground if c->hits_ground, else to the top), per channel; nu is
 * clamped into what mu and mu_s allow. transmittance: the table set's
 * transmittance table in the parameterisation of p. */
void sf_sunlit_ray(const sf_atmosphere *atm, const sf_table_params *p, const sf_table *transmittance, int n,
                   const int *constituents, const sf_scattering_coord *c, double out[][SF_MAX_CHANNELS]);

#endif
