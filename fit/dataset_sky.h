/* Training sets of the neural sky from the reference tables (SPEC §6,
 * §7.4-7.5), restricted to a scene's domain (SPEC §5, sf_scene_get_domain).
 * The samples are the tables' own grid points (exact reference values, no
 * interpolation); inputs are normalised to [-1, 1] over the domain as
 * models/mlp_sky.h describes, and the normalisation is kept in the dataset
 * for the weights file. Needs tables in Bruneton's parameterisation, whose
 * transmittance table holds exactly the rays to the top boundary that the
 * transmittance network learns. */
#ifndef SKYFIT_FIT_DATASET_SKY_H
#define SKYFIT_FIT_DATASET_SKY_H

#include "data/table_set.h"
#include "fit/dataset.h"
#include "models/mlp_sky.h"
#include "models/scene_file.h"

/* Rays of the transmittance network: altitudes and directions it must
 * cover. Rays hitting the ground are evaluated reversed (eq. 43), so if the
 * domain has any, the network covers the ground (h = 0) and every upward
 * ray; otherwise [h_min, h_max] and mu >= mu_min. */
typedef struct sf_transmittance_domain {
  double h_min, h_max, mu_min;
} sf_transmittance_domain;
void sf_transmittance_domain_of(const sf_atmosphere *atm, const sf_scene_domain *dom,
                                sf_transmittance_domain *out);

/* Inputs (sqrt_h_km, mu) -> T_top per channel, at the transmittance table's
 * grid points inside the domain. */
int sf_dataset_transmittance(const sf_table_set *set, const sf_atmosphere *atm, const sf_scene_domain *dom,
                             sf_dataset *d, sf_error *err);
/* The same samples with the inputs of map (models/mlp_sky.h): (sqrt_h_km,
 * mu) as above, or Bruneton's (x_r, x_mu), each normalised to [-1, 1] over
 * the domain's range. */
int sf_dataset_transmittance_mapped(const sf_table_set *set, const sf_atmosphere *atm, const sf_scene_domain *dom,
                                    sf_mlp_input_map map, sf_dataset *d, sf_error *err);

/* Inputs (sqrt_h_km, mu, mu_s, nu) -> the target's outputs (models/mlp_sky.h)
 * at the scattering tables' grid points inside the domain (nu clamped).
 * For target separate, *n_single and constituent[] say which constituent each
 * single-scattering block is. */
int sf_dataset_scattering(const sf_table_set *set, const sf_atmosphere *atm, const sf_scene_domain *dom,
                          sf_mlp_target target, sf_dataset *d, int *n_single, int *constituent,
                          sf_error *err);
/* Fewer samples than this in either half (rays of length 0, from h = 0 to
 * the ground, not counted): one network for both. */
#define SF_MLP_SPLIT_MIN_SAMPLES 1000
/* The same samples in the two sets of the horizon split (models/mlp_sky.h):
 * rays that leave through the top, and rays that end on the ground (as the
 * table's halves hold them), each in the order above, with the same
 * normalisation. With fewer than SF_MLP_SPLIT_MIN_SAMPLES in either half,
 * every sample goes to sky, in the order of sf_dataset_scattering, and
 * ground is left empty: train one network. */
int sf_dataset_scattering_halves(const sf_table_set *set, const sf_atmosphere *atm, const sf_scene_domain *dom,
                                 sf_mlp_target target, sf_dataset *sky, sf_dataset *ground, int *n_single,
                                 int *constituent, sf_error *err);

#endif
