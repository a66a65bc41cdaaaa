/* Sky radiance from the reference tables (SPEC §6 "sky radiance seen from
 * any viewer"), Bruneton's GetSkyRadiance: the single-scattering tables of
 * every scattering constituent times its phase function at nu, plus the
 * multiple-scattering table, all interpolated multilinearly in the table's
 * parameterisation (data/table_params.h), the single scattering of a low
 * sun, or of a ray that keeps to the top altitude cell, divided by the
 * ray's sunlit air (data/sunlit_ray.h) to be interpolated and multiplied
 * back. A viewer above the top of the
 * atmosphere is moved along the ray to where it enters (nothing if it never
 * does). The direct sun and the ground seen at the end of the ray are not
 * included. */
#ifndef SKYFIT_DATA_SKY_LOOKUP_H
#define SKYFIT_DATA_SKY_LOOKUP_H

#include "data/sample_memo.h"
#include "data/table.h"
#include "data/table_params.h"
#include "data/table_set.h"
#include "models/atmosphere.h"

/* Views of the tables (not owned). */
typedef struct sf_sky_tables {
  const sf_atmosphere *atm;
  sf_table_params params;
  const sf_table *transmittance;
  int n_single;
  int single_constituent[SF_MAX_CONSTITUENTS];
  const sf_table *single[SF_MAX_CONSTITUENTS];
  const sf_table *multiple;
  /* The set's memo of F at the single tables' samples (data/table_set.h;
   * not owned, shared between threads); NULL: F computed at every lookup. */
  sf_sample_memo *sunlit;
} sf_sky_tables;

void sf_sky_tables_of_set(sf_sky_tables *sky, const sf_atmosphere *atm, const sf_table_set *set);

typedef struct sf_sky_sample {
  int in_atmosphere;      /* 0: the ray never enters it (everything 0) */
  double single[SF_MAX_CONSTITUENTS][SF_MAX_CHANNELS];  /* per single table, no phase */
  double multiple[SF_MAX_CHANNELS];
  double radiance[SF_MAX_CHANNELS];   /* sum_c phase_c(nu) single_c + multiple */
} sf_sky_sample;

/* Moves a viewer at altitude h above the top to where its ray (mu, sun at
 * mu_s, view-sun cosine nu) enters. Returns 0 if the ray never enters;
 * else fills r, mu, mu_s at the (new) viewer (unchanged inside). */
int sf_sky_enter_atmosphere(const sf_atmosphere *atm, double h, double *r, double *mu, double *mu_s, double nu);

/* Viewer at altitude h_km (>= 0, may be above the top) looking along mu, sun
 * at mu_s, view-sun cosine nu (clamped into what mu and mu_s allow). */
void sf_sky_lookup(const sf_sky_tables *sky, double h_km, double mu, double mu_s, double nu,
                   sf_sky_sample *out);

/* The transmittance table's T from altitude h along mu to the top (Bruneton
 * 2017 GetTransmittanceToTopAtmosphereBoundary), per channel. Returns 0, or
 * nonzero where the parameterisation refuses the ray (Bruneton's: one that
 * passes below the ground), out then holding the table's first entry. */
int sf_transmittance_table_to_top(const sf_table_params *p, const sf_table *transmittance, double h, double mu,
                                  double *out);

/* Transmittance along the same ray to its end (the ground or the top); 1 if
 * the ray never enters the atmosphere. Bruneton's table holds rays to the
 * top only: a ray to the ground is the ratio of two of them (Bruneton 2017
 * GetTransmittance). */
void sf_sky_transmittance(const sf_sky_tables *sky, double h_km, double mu, double *transmittance);

#endif
