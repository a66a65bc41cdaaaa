#include "fit/dataset_sky.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "models/phase.h"
#include "models/ray_geometry.h"
#include "models/single_scattering.h"

#define DOMAIN_TOL 1e-9

/* normalised = (value - offset) * scale maps [lo, hi] to [-1, 1]. */
static void set_input(sf_dataset *d, int k, const char *name, double lo, double hi) {
  snprintf(d->names[k], SF_DATASET_NAME_LEN, "%s", name);
  d->input_offset[k] = 0.5 * (lo + hi);
  d->input_scale[k] = hi > lo ? 2.0 / (hi - lo) : 1.0;
}

static double norm_input(const sf_dataset *d, int k, double v) {
  return (v - d->input_offset[k]) * d->input_scale[k];
}

void sf_transmittance_domain_of(const sf_atmosphere *atm, const sf_scene_domain *dom,
                                sf_transmittance_domain *out) {
  double R = atm->bottom_radius_km;
  double top = atm->top_radius_km - R;
  double h_max = fmin(dom->h_max_km, top);
  double h_min = fmin(dom->h_min_km, h_max);
  int ground_rays = dom->mu_min < sf_horizon_mu(R + h_min, R) || h_min <= 0.0;
  out->h_min = ground_rays ? 0.0 : h_min;
  out->h_max = h_max;
  out->mu_min = ground_rays ? -1.0 : dom->mu_min;
}

int sf_dataset_transmittance(const sf_table_set *set, const sf_atmosphere *atm, const sf_scene_domain *dom,
                             sf_dataset *d, sf_error *err) {
  return sf_dataset_transmittance_mapped(set, atm, dom, SF_MLP_INPUTS_SQRT_H_MU, d, err);
}

/* The two network inputs of (h, mu) under map, before normalisation. */
static void mapped_inputs(const sf_atmosphere *atm, sf_mlp_input_map map, double h, double mu, double *v) {
  if (map == SF_MLP_INPUTS_BRUNETON) {
    sf_mlp_bruneton_coords(atm->bottom_radius_km, atm->top_radius_km, h, mu, &v[0], &v[1]);
  } else {
    v[0] = sqrt(fmax(h, 0.0));
    v[1] = mu;
  }
}

int sf_dataset_transmittance_mapped(const sf_table_set *set, const sf_atmosphere *atm, const sf_scene_domain *dom,
                                    sf_mlp_input_map map, sf_dataset *d, sf_error *err) {
  memset(d, 0, sizeof *d);
  if (set->params.kind != SF_PARAM_BRUNETON)
    return sf_fail(err, SF_ERR_INPUT, "the transmittance network is trained on Bruneton's tables (rays to the top)");
  sf_transmittance_domain td;
  sf_transmittance_domain_of(atm, dom, &td);
  const sf_table *t = &set->transmittance;
  int n0 = t->desc.axes[0].size, n1 = t->desc.axes[1].size;
  long count = 0;
  for (int pass = 0; pass < 2; ++pass) {
    if (pass == 1) {
      if (sf_dataset_init(d, count, 2, atm->n_channels, err)) return err->status;
      if (map == SF_MLP_INPUTS_BRUNETON) {
        /* x_r grows with h; x_mu spans [0, 1] at every altitude */
        double lo[2], hi[2];
        mapped_inputs(atm, map, td.h_min, 1.0, lo);
        mapped_inputs(atm, map, td.h_max, 1.0, hi);
        set_input(d, 0, sf_mlp_input_map_input_name(map, 0), lo[0], hi[0]);
        set_input(d, 1, sf_mlp_input_map_input_name(map, 1), 0.0, 1.0);
      } else {
        set_input(d, 0, "sqrt_h_km", sqrt(td.h_min), sqrt(td.h_max));
        set_input(d, 1, "mu", td.mu_min, 1.0);
      }
      for (int c = 0; c < atm->n_channels; ++c)
        snprintf(d->names[2 + c], SF_DATASET_NAME_LEN, "T_%s", atm->channel_names[c]);
      count = 0;
    }
    for (int i1 = 0; i1 < n1; ++i1)
      for (int i0 = 0; i0 < n0; ++i0) {
        double pos[2] = {i0, i1}, h, mu;
        sf_params_transmittance_coord(&set->params, pos, &h, &mu);
        if (h < td.h_min - DOMAIN_TOL || h > td.h_max + DOMAIN_TOL || mu < td.mu_min - DOMAIN_TOL) continue;
        if (pass == 1) {
          int index[2] = {i0, i1};
          const float *v = sf_table_at(t, index);
          double in[2];
          mapped_inputs(atm, map, h, mu, in);
          d->x[count * 2 + 0] = norm_input(d, 0, in[0]);
          d->x[count * 2 + 1] = norm_input(d, 1, in[1]);
          for (int c = 0; c < atm->n_channels; ++c) d->y[count * atm->n_channels + c] = v[c];
        }
        ++count;
      }
    if (count == 0) return sf_fail(err, SF_ERR_INPUT, "the scene's domain holds no transmittance table sample");
  }
  return SF_OK;
}

/* Row kinds of the horizon split. */
#define ROW_SKY 0
#define ROW_GROUND 1
#define ROW_GROUND_LENGTH_0 2   /* from h = 0 toward the ground: the model's exact 0 */

/* sf_dataset_scattering; with ground_of, also an array (allocated here, one
 * byte per row) saying whether the row's ray ends on the ground, as the
 * table's half holds it (ROW_*). */
static int scattering_rows(const sf_table_set *set, const sf_atmosphere *atm, const sf_scene_domain *dom,
                           sf_mlp_target target, sf_dataset *d, int *n_single, int *constituent,
                           unsigned char **ground_of, sf_error *err) {
  memset(d, 0, sizeof *d);
  if (set->params.kind != SF_PARAM_BRUNETON)
    return sf_fail(err, SF_ERR_INPUT, "the scattering network is trained on Bruneton's tables");
  if (target == SF_MLP_TARGET_TRANSMITTANCE_TOP)
    return sf_fail(err, SF_ERR_INPUT, "target transmittance_top is not a scattering target");
  int nch = atm->n_channels;
  *n_single = set->n_single;
  for (int k = 0; k < set->n_single; ++k) constituent[k] = set->single_constituent[k];
  int n_out = target == SF_MLP_TARGET_SEPARATE ? (set->n_single + 1) * nch : nch;
  double top = atm->top_radius_km - atm->bottom_radius_km;
  double h_max = fmin(dom->h_max_km, top), h_min = fmin(dom->h_min_km, h_max);
  const sf_table *ms = &set->multiple;
  int size[4];
  for (int a = 0; a < 4; ++a) size[a] = ms->desc.axes[a].size;
  long count = 0;
  for (int pass = 0; pass < 2; ++pass) {
    if (pass == 1) {
      if (sf_dataset_init(d, count, 4, n_out, err)) return err->status;
      if (ground_of && !(*ground_of = malloc((size_t)count))) {
        sf_dataset_free(d);
        return sf_fail(err, SF_ERR_INTERNAL, "out of memory");
      }
      set_input(d, 0, "sqrt_h_km", sqrt(h_min), sqrt(h_max));
      set_input(d, 1, "mu", dom->mu_min, dom->mu_max);
      set_input(d, 2, "mu_s", dom->mu_s_min, dom->mu_s_max);
      set_input(d, 3, "nu", -1.0, 1.0);
      int col = 4;
      if (target == SF_MLP_TARGET_SEPARATE) {
        for (int k = 0; k < set->n_single; ++k)
          for (int c = 0; c < nch; ++c)
            snprintf(d->names[col++], SF_DATASET_NAME_LEN, "%.20s_%s",
                     atm->constituents[constituent[k]].name, atm->channel_names[c]);
        for (int c = 0; c < nch; ++c) snprintf(d->names[col++], SF_DATASET_NAME_LEN, "multiple_%s", atm->channel_names[c]);
      } else {
        for (int c = 0; c < nch; ++c) snprintf(d->names[col++], SF_DATASET_NAME_LEN, "L_%s", atm->channel_names[c]);
      }
      count = 0;
    }
    int idx[4];
    for (idx[3] = 0; idx[3] < size[3]; ++idx[3])
      for (idx[2] = 0; idx[2] < size[2]; ++idx[2])
        for (idx[1] = 0; idx[1] < size[1]; ++idx[1])
          for (idx[0] = 0; idx[0] < size[0]; ++idx[0]) {
            double pos[4] = {idx[0], idx[1], idx[2], idx[3]};
            sf_scattering_coord c;
            sf_params_scattering_coord(&set->params, pos, &c);
            if (c.h < h_min - DOMAIN_TOL || c.h > h_max + DOMAIN_TOL || c.mu < dom->mu_min - DOMAIN_TOL ||
                c.mu > dom->mu_max + DOMAIN_TOL || c.mu_s < dom->mu_s_min - DOMAIN_TOL ||
                c.mu_s > dom->mu_s_max + DOMAIN_TOL)
              continue;
            if (pass == 1) {
              double nu = sf_clamp_nu(c.mu, c.mu_s, c.nu);
              double *x = d->x + count * 4, *y = d->y + count * n_out;
              x[0] = norm_input(d, 0, sqrt(fmax(c.h, 0.0)));
              x[1] = norm_input(d, 1, c.mu);
              x[2] = norm_input(d, 2, c.mu_s);
              x[3] = norm_input(d, 3, nu);
              if (ground_of)
                (*ground_of)[count] = !c.hits_ground ? ROW_SKY : c.h > DOMAIN_TOL ? ROW_GROUND : ROW_GROUND_LENGTH_0;
              const float *m = sf_table_at(ms, idx);
              if (target == SF_MLP_TARGET_SEPARATE) {
                for (int k = 0; k < set->n_single; ++k) {
                  const float *s = sf_table_at(&set->single[k], idx);
                  for (int ch = 0; ch < nch; ++ch) y[k * nch + ch] = s[ch];
                }
                for (int ch = 0; ch < nch; ++ch) y[set->n_single * nch + ch] = m[ch];
              } else {
                for (int ch = 0; ch < nch; ++ch) y[ch] = m[ch];
                for (int k = 0; k < set->n_single; ++k) {
                  const float *s = sf_table_at(&set->single[k], idx);
                  double phase = sf_phase_value(&atm->constituents[constituent[k]].phase, nu);
                  for (int ch = 0; ch < nch; ++ch) y[ch] += phase * s[ch];
                }
              }
            }
            ++count;
          }
    if (count == 0) return sf_fail(err, SF_ERR_INPUT, "the scene's domain holds no scattering table sample");
  }
  return SF_OK;
}

int sf_dataset_scattering(const sf_table_set *set, const sf_atmosphere *atm, const sf_scene_domain *dom,
                          sf_mlp_target target, sf_dataset *d, int *n_single, int *constituent,
                          sf_error *err) {
  return scattering_rows(set, atm, dom, target, d, n_single, constituent, NULL, err);
}

/* Copies the rows whose ray ends on the ground (ground 1) or not (0), names
 * and normalisation too. */
static int rows_where(const sf_dataset *all, const unsigned char *flag, int ground, sf_dataset *out,
                      sf_error *err) {
  long n = 0;
  for (long i = 0; i < all->n; ++i) n += (flag[i] != ROW_SKY) == ground;
  if (sf_dataset_init(out, n, all->n_in, all->n_out, err)) return err->status;
  memcpy(out->names, all->names, sizeof out->names);
  memcpy(out->input_offset, all->input_offset, sizeof out->input_offset);
  memcpy(out->input_scale, all->input_scale, sizeof out->input_scale);
  long k = 0;
  for (long i = 0; i < all->n; ++i) {
    if ((flag[i] != ROW_SKY) != ground) continue;
    memcpy(out->x + k * all->n_in, all->x + i * all->n_in, sizeof(double) * (size_t)all->n_in);
    memcpy(out->y + k * all->n_out, all->y + i * all->n_out, sizeof(double) * (size_t)all->n_out);
    ++k;
  }
  return SF_OK;
}

int sf_dataset_scattering_halves(const sf_table_set *set, const sf_atmosphere *atm, const sf_scene_domain *dom,
                                 sf_mlp_target target, sf_dataset *sky, sf_dataset *ground, int *n_single,
                                 int *constituent, sf_error *err) {
  memset(sky, 0, sizeof *sky);
  memset(ground, 0, sizeof *ground);
  sf_dataset all;
  unsigned char *flag = NULL;
  int status = scattering_rows(set, atm, dom, target, &all, n_single, constituent, &flag, err);
  /* Rays of length 0 do not count: the model never asks a network for them,
   * so a scene whose viewers stand on the ground (every ray to the ground of
   * length 0) gets one network, not a second one trained on zeros. They
   * still go to the ground half when it is trained. */
  long n_sky = 0, n_ground = 0;
  for (long i = 0; status == SF_OK && i < all.n; ++i) {
    n_sky += flag[i] == ROW_SKY;
    n_ground += flag[i] == ROW_GROUND;
  }
  if (status == SF_OK && (n_ground < SF_MLP_SPLIT_MIN_SAMPLES || n_sky < SF_MLP_SPLIT_MIN_SAMPLES)) {
    *sky = all;   /* one network: every sample, ground left empty */
    free(flag);
    return SF_OK;
  }
  if (status == SF_OK) status = rows_where(&all, flag, 0, sky, err);
  if (status == SF_OK) status = rows_where(&all, flag, 1, ground, err);
  if (status != SF_OK) {
    sf_dataset_free(sky);
    sf_dataset_free(ground);
  }
  sf_dataset_free(&all);
  free(flag);
  return status;
}
