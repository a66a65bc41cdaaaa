#include "data/table_set.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "data/phase_peak.h"
#include "data/precompute_single.h"
#include "data/precompute_transmittance.h"
#include "data/scattering_setup.h"
#include "data/table_cache.h"
#include "data/table_interp.h"
#include "models/atmosphere_file.h"
#include "util/memory_limit.h"

int sf_table_set_orders_short(const sf_table_set *set, const sf_table_set_options *o, char *text, size_t n) {
  /* the multiple table's own record, so a cached table says it too */
  const sf_table_orders *r = &set->multiple.orders;
  if (!(o->stop_fraction > 0.0) || r->highest != o->orders || o->orders < 3 || r->left_fraction < o->stop_fraction)
    return 0;
  if (!isfinite(r->left_fraction)) {   /* no tail: data/precompute_multiple.c adds one where the orders shrink */
    snprintf(text, n,
             "multiple scattering: after order %d, the most asked for, the orders were not yet shrinking in its "
             "slowest channel (the stop fraction is %g): the orders left are not estimated, and the tables lack them",
             r->highest, o->stop_fraction);
    return 1;
  }
  snprintf(text, n,
           "multiple scattering: after order %d, the most asked for, the orders left would still add about %.3g of "
           "the sky radiance in its slowest channel (the stop fraction is %g), summed over all the tables' entries "
           "and estimated as a geometric tail, which the tables hold in place of those orders: an estimate, least "
           "sure in their dim parts (the ground under an optically thick atmosphere, where each order is nearly "
           "the last)",
           r->highest, r->left_fraction, o->stop_fraction);
  return 1;
}

void sf_table_set_options_default(sf_table_set_options *o) {
  memset(o, 0, sizeof *o);
  o->kind = SF_PARAM_BRUNETON;
  sf_table_resolution_default(&o->res);
  o->orders = SF_TABLE_SET_DEFAULT_ORDERS;
  o->stop_fraction = SF_TABLE_SET_DEFAULT_STOP_FRACTION;
}

static size_t scattering_entries(const sf_table_resolution *r) {
  return (size_t)r->scattering_h * (size_t)r->scattering_mu * (size_t)r->scattering_mu_s *
         (size_t)r->scattering_nu;
}

size_t sf_table_set_memory_bytes(const sf_atmosphere *atm, const sf_table_set_options *o) {
  /* Counts are checked to be <= SF_TABLE_MAX_AXIS_SIZE (2^16) each, so the
   * products below are computed in double to stay clear of overflow. */
  double nch = atm->n_channels, ns = 0;
  for (int i = 0; i < atm->n_constituents; ++i) ns += sf_constituent_scatters(&atm->constituents[i], atm->n_channels);
  const sf_table_resolution *r = &o->res;
  double entries = (double)r->scattering_h * r->scattering_mu * r->scattering_mu_s * r->scattering_nu;
  double internal = (double)r->scattering_h * (r->scattering_mu + 1) * r->scattering_mu_s * r->scattering_nu;
  double bytes = 4.0 * nch * ((double)r->transmittance_mu * r->transmittance_h +
                              (double)r->irradiance_mu_s * r->irradiance_h);
  if (o->transmittance_only) {
    ns = 0;
    entries = 0;
  }
  bytes += 4.0 * nch * entries * (ns + 1.0);                /* output singles, multiple */
  bytes += entries * (8.0 * ns * nch + 1.0);   /* the lookups' memo of F, all of it (data/sample_memo.h) */
  if (o->orders >= 2 && ns > 0) {
    /* an output apart from the internal grid: Leenman, or a restricted domain */
    double leenman = o->kind == SF_PARAM_LEENMAN || o->has_domain;
    /* internal singles (Leenman), previous and current order, G (and its
     * sum for Leenman), the double sum of orders */
    bytes += 4.0 * nch * internal * (leenman * ns + 2.0 + ns * (1.0 + leenman)) + 8.0 * nch * internal;
  }
  bytes += 8.0 * SF_DEPTH_GRID_MU * SF_DEPTH_GRID_H * atm->n_constituents;
  return bytes > 1e18 ? (size_t)1e18 : (size_t)bytes;
}

int sf_table_set_check(const sf_atmosphere *atm, const sf_table_set_options *o, sf_error *err) {
  if (sf_table_resolution_check(&o->res, o->kind, err) != SF_OK) return SF_ERR_INPUT;
  if (o->orders < 1 || o->orders > SF_MULTIPLE_MAX_ORDERS)
    return sf_fail(err, SF_ERR_INPUT, "orders: %d is outside 1..%d", o->orders, SF_MULTIPLE_MAX_ORDERS);
  if (!(o->stop_fraction >= 0.0 && o->stop_fraction < 1.0))
    return sf_fail(err, SF_ERR_INPUT, "stop fraction %g must be in [0, 1)", o->stop_fraction);
  for (int i = 0; i < atm->n_constituents; ++i) {
    if (!sf_constituent_scatters(&atm->constituents[i], atm->n_channels)) continue;
    char name[SF_TABLE_NAME_LEN];
    if (sf_single_table_name(&atm->constituents[i], name, err) != SF_OK) return SF_ERR_INPUT;
  }
  if (o->has_domain) {
    sf_table_params p;
    sf_table_params_make(&p, atm, o->kind, &o->res);
    if (sf_table_params_restrict(&p, &o->domain, err) != SF_OK) return SF_ERR_INPUT;
  }
  size_t need = sf_table_set_memory_bytes(atm, o);
  char source[512];
  size_t limit = sf_memory_limit_bytes(source, sizeof source);
  if (need > limit || scattering_entries(&o->res) > ((size_t)1 << 34))
    return sf_fail(err, SF_ERR_INPUT,
                   "resolution %dx%d,%dx%dx%dx%d needs about %.2f GiB of memory for the tables "
                   "(limit %.2f GiB: %s)", o->res.transmittance_mu, o->res.transmittance_h, o->res.scattering_h,
                   o->res.scattering_mu, o->res.scattering_mu_s, o->res.scattering_nu,
                   (double)need / (1 << 30), (double)limit / (1 << 30), source);
  return SF_OK;
}


/* Sets the key of desc and tries the cache; returns 1 if *t was loaded. */
static int try_cache(const sf_table_set_options *o, sf_table_desc *desc, const char *json, int orders,
                     const char *version, sf_table *t, char *path, size_t path_size) {
  sf_table_cache_key(desc, json, orders, version, desc->content_hash);
  path[0] = '\0';
  if (!o->cache_dir) return 0;
  sf_error ignored = {0};
  sf_table_cache_path(o->cache_dir, desc->quantity, desc->content_hash, path, path_size, &ignored);
  sf_error problem = {0};
  char text[2048];
  if (sf_table_cache_load(o->cache_dir, desc, 0, t, &problem)) {
    snprintf(text, sizeof text, "%.31s: loaded from the cache (%.1900s)", desc->quantity, path);
    if (o->note) o->note(o->note_ctx, text);
    return 1;
  }
  if (problem.status != SF_OK) {
    snprintf(text, sizeof text, "%.1900s; recomputing it", problem.message);
    if (o->problem) o->problem(o->problem_ctx, text);
    else if (o->note) o->note(o->note_ctx, text);
  }
  return 0;
}

void sf_table_set_free(sf_table_set *set) {
  sf_table_free(&set->transmittance);
  for (int k = 0; k < SF_MAX_CONSTITUENTS; ++k) sf_table_free(&set->single[k]);
  sf_table_free(&set->multiple);
  sf_table_free(&set->irradiance);
  sf_sample_memo_free(set->single_sunlit);
  memset(set, 0, sizeof *set);
}

int sf_table_set_make(sf_table_set *set, const sf_atmosphere *atm, const sf_table_set_options *o,
                      sf_error *err) {
  memset(set, 0, sizeof *set);
  if (sf_table_set_check(atm, o, err) != SF_OK) return SF_ERR_INPUT;
  char *json = sf_atmosphere_to_json(atm);
  if (!json) return sf_fail(err, SF_ERR_INTERNAL, "out of memory for the atmosphere's JSON");
  sf_table_params_make(&set->params, atm, o->kind, &o->res);
  if (o->has_domain && sf_table_params_restrict(&set->params, &o->domain, err) != SF_OK) {
    free(json);
    return SF_ERR_INPUT;
  }
  const sf_table_params *p = &set->params;

  /* descriptions and keys; multiple scattering depends on the orders, and
   * the irradiance also on the internal scattering grid it is gathered on
   * (precompute_multiple.h), which its own axes do not show */
  char version_multiple[128], version_irradiance[192];
  snprintf(version_multiple, sizeof version_multiple, "%s; stop %.17g", SF_TABLES_CODE_VERSION, o->stop_fraction);
  sf_table_params internal_grid;
  sf_multiple_internal_params(p, &internal_grid);
  snprintf(version_irradiance, sizeof version_irradiance, "%s; scattering grid %dx%dx%dx%d", version_multiple,
           internal_grid.res.scattering_h, internal_grid.res.scattering_mu, internal_grid.res.scattering_mu_s,
           internal_grid.res.scattering_nu);
  sf_table_desc desc[SF_TABLE_SET_MAX_TABLES];
  int n = 0, status = SF_OK;
  status |= sf_params_transmittance_desc(p, atm, &desc[n], err);
  set->tables[n++] = &set->transmittance;
  for (int i = 0; i < atm->n_constituents && status == SF_OK && !o->transmittance_only; ++i) {
    if (!sf_constituent_scatters(&atm->constituents[i], atm->n_channels)) continue;
    char name[SF_TABLE_NAME_LEN];
    status |= sf_single_table_name(&atm->constituents[i], name, err);
    if (status == SF_OK) status |= sf_params_scattering_desc(p, atm, name, &desc[n], err);
    set->single_constituent[set->n_single] = i;
    set->tables[n++] = &set->single[set->n_single++];
  }
  int i_multiple = n;
  if (!o->transmittance_only) {
    if (status == SF_OK) status |= sf_params_scattering_desc(p, atm, "multiple", &desc[n], err);
    set->tables[n++] = &set->multiple;
    if (status == SF_OK) status |= sf_params_irradiance_desc(p, atm, &desc[n], err);
    set->tables[n++] = &set->irradiance;
  }
  set->n_tables = n;
  if (status != SF_OK) {
    free(json);
    return SF_ERR_INPUT;
  }

  int single_missing = 0, multiple_missing = 0;
  for (int t = 0; t < n; ++t) {
    int orders = t >= i_multiple ? o->orders : 0;
    const char *version = set->tables[t] == &set->irradiance ? version_irradiance
                          : t >= i_multiple                  ? version_multiple
                                                             : SF_TABLES_CODE_VERSION;
    set->from_cache[t] = try_cache(o, &desc[t], json, orders, version, set->tables[t], set->paths[t],
                                   sizeof set->paths[t]);
    if (set->from_cache[t]) continue;
    if (t > 0 && t < i_multiple) single_missing = 1;
    if (t >= i_multiple) multiple_missing = 1;
    if (sf_table_init(set->tables[t], &desc[t], json, 0, err) != SF_OK) {
      free(json);
      sf_table_set_free(set);
      return err->status;
    }
  }

  if (!set->from_cache[0])
    status = sf_precompute_transmittance(atm, p, &o->run, &set->transmittance, err);
  sf_scattering_setup setup;
  memset(&setup, 0, sizeof setup);
  if (status == SF_OK && (single_missing || multiple_missing))
    status = sf_scattering_setup_init(&setup, atm, &o->run, err);
  if (status == SF_OK && single_missing && set->n_single > 0)
    status = sf_precompute_single(&setup, p, &o->run, set->single, err);
  if (status == SF_OK && multiple_missing) {
    /* the internal grid's singles are the output's when both are Bruneton
     * at the same resolution; otherwise they are computed here */
    sf_table_params internal;
    sf_multiple_internal_params(p, &internal);
    sf_table internal_single[SF_MAX_CONSTITUENTS];
    memset(internal_single, 0, sizeof internal_single);
    const sf_table *singles = set->single;
    int own = p->kind != SF_PARAM_BRUNETON || internal.res.scattering_mu != p->res.scattering_mu ||
              p->restricted;
    if (own && set->n_single > 0 && o->orders >= 2) {
      for (int k = 0; k < set->n_single && status == SF_OK; ++k) {
        sf_table_desc d;
        status = sf_params_scattering_desc(&internal, atm, set->single[k].desc.quantity, &d, err);
        if (status == SF_OK) status = sf_table_init(&internal_single[k], &d, "", 0, err);
      }
      if (status == SF_OK) status = sf_precompute_single(&setup, &internal, &o->run, internal_single, err);
      singles = internal_single;
    }
    sf_multiple_options mo = {o->orders, o->stop_fraction};
    if (status == SF_OK)
      status = sf_precompute_multiple(&setup, p, singles, &mo, &o->run, &set->multiple, &set->irradiance,
                                      &set->report, err);
    set->multiple_computed = status == SF_OK;
    if (set->multiple_computed && set->report.highest_order >= 2)
      set->multiple.orders = (sf_table_orders){set->report.highest_order,
                                               set->report.remaining_fraction[set->report.highest_order]};
    for (int k = 0; k < SF_MAX_CONSTITUENTS; ++k) sf_table_free(&internal_single[k]);
  }
  sf_scattering_setup_free(&setup);
  /* computed or cached: the multiple table keeps how its orders ended */
  char orders_text[640];
  if (status == SF_OK && o->note && !o->transmittance_only &&
      sf_table_set_orders_short(set, o, orders_text, sizeof orders_text))
    o->note(o->note_ctx, orders_text);
  /* the atmosphere's, so said whether the tables were computed or cached */
  char peak_text[640];
  if (status == SF_OK && o->note && !o->transmittance_only && o->orders >= 2 &&
      sf_phase_peaks_note(atm, peak_text, sizeof peak_text))
    o->note(o->note_ctx, peak_text);

  /* Finite numbers of float32 only, before anything is stored: a sun of
   * 1e39 passes the atmosphere file's checks, and its tables held inf:
   * `sample` wrote the transmittance table and then failed (exit 1), and
   * `eval sky_radiance` read them. */
  for (int t = 0; t < n && status == SF_OK; ++t) {
    if (set->from_cache[t]) continue;
    const sf_table *table = set->tables[t];
    size_t count = (size_t)sf_table_desc_points(&table->desc) * (size_t)table->desc.n_channels;
    for (size_t i = 0; i < count; ++i)
      if (!isfinite(table->data[i])) {
        status = sf_fail(err, SF_ERR_INPUT,
                         "atmosphere %s: its %s table holds %g (channel %s): its coefficients or sun irradiance "
                         "are too large for tables of float32 numbers",
                         atm->name, table->desc.quantity, (double)table->data[i],
                         table->desc.channel_names[i % (size_t)table->desc.n_channels]);
        break;
      }
  }
  for (int t = 0; t < n && status == SF_OK && o->cache_dir; ++t) {
    if (set->from_cache[t]) continue;
    status = sf_table_cache_store(o->cache_dir, set->tables[t], err);
  }
  free(json);
  /* the memo of F at the single tables' samples, sliced along mu_s (the
   * axis orders of data/table_params.h) so that no storage is taken for
   * the high suns until a ray that keeps to the top altitude cell asks for
   * F there (data/sky_lookup.c) */
  if (status == SF_OK && set->n_single > 0) {
    set->atmosphere_hash = sf_atmosphere_hash(atm);
    sf_grid_view g = sf_grid_view_of(&set->single[0]);
    set->single_sunlit = sf_sample_memo_make(g.size, p->kind == SF_PARAM_BRUNETON ? 0 : 2,
                                             set->n_single * atm->n_channels);
    if (!set->single_sunlit)
      status = sf_fail(err, SF_ERR_INTERNAL, "out of memory for the memo of the single tables' sunlit air");
  }
  if (status != SF_OK) {
    sf_table_set_free(set);
    return err->status ? err->status : SF_ERR_INTERNAL;
  }
  return SF_OK;
}
