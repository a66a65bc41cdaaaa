#include "fit/candidate_registry.h"

#include <stdio.h>
#include <string.h>

#include "fit/candidate_builtin.h"
#include "fit/candidate_cache.h"
#include "fit/candidate_fitted.h"
#include "util/make_folders.h"

/* One line per fitted model, and per baseline fitted to the tables (the
 * published skies' turbidity and factors) (fit/candidate_fitted.h). */
static const sf_candidate_factory factories[] = {
    {"sigmoid", SF_CANDIDATE_TRANSMITTANCE, sf_candidate_applies_sigmoid, sf_candidate_make_sigmoid, 0},
    {"mlp-transmittance", SF_CANDIDATE_TRANSMITTANCE, sf_candidate_applies_mlp_transmittance,
     sf_candidate_make_mlp_transmittance, 1},
    {"preetham", SF_CANDIDATE_SKY_RADIANCE, sf_candidate_applies_preetham, sf_candidate_make_preetham, 0},
    {"hosek", SF_CANDIDATE_SKY_RADIANCE, sf_candidate_applies_hosek, sf_candidate_make_hosek, 0},
    {"preetham-published", SF_CANDIDATE_SKY_RADIANCE, sf_candidate_applies_preetham_published,
     sf_candidate_make_preetham_published, 0},
    {"hosek-published", SF_CANDIDATE_SKY_RADIANCE, sf_candidate_applies_hosek_published,
     sf_candidate_make_hosek_published, 0},
    {"mlp-scattering", SF_CANDIDATE_SKY_RADIANCE, sf_candidate_applies_mlp_scattering,
     sf_candidate_make_mlp_scattering, 1},
};

int sf_candidate_factories(const sf_candidate_factory **out) {
  *out = factories;
  return (int)(sizeof factories / sizeof factories[0]);
}

static int add(sf_candidate_list *list, sf_candidate *c, sf_error *err) {
  if (sf_candidate_list_add(list, c) != 0) return sf_fail(err, SF_ERR_INTERNAL, "out of memory");
  return SF_OK;
}

static void say(sf_candidate_note_fn note, void *ctx, const char *fmt, const char *a, const char *b) {
  if (!note) return;
  char text[1200];
  snprintf(text, sizeof text, fmt, a, b);
  note(ctx, text);
}

int sf_candidate_sky_tables_ready(const sf_candidate_inputs *in, char *why, size_t why_len) {
  if (sf_atmosphere_scattering_count(in->atm) == 0) {
    snprintf(why, why_len,
             "no constituent of %s scatters light (every scattering coefficient is 0): its sky radiance is 0 "
             "everywhere, and there is nothing to fit",
             in->atm->name);
    return 0;
  }
  if (!in->sky || !in->tables || in->tables->n_single < 1) {
    snprintf(why, why_len, "it is fitted to the sky-radiance tables, which this build has not made");
    return 0;
  }
  return 1;
}

/* Every registered factory of quantity q that applies (only the
 * restartable ones if restartable_only), made and added to list. */
static int make_fitted(const sf_candidate_inputs *in, sf_candidate_quantity q, int restartable_only,
                       sf_candidate_list *list, int *n_added, sf_candidate_note_fn note, void *note_ctx,
                       sf_error *err) {
  const sf_candidate_factory *f;
  int n = sf_candidate_factories(&f);
  for (int i = 0; i < n; ++i) {
    if (f[i].quantity != q || (restartable_only && !f[i].restartable)) continue;
    if (sf_candidate_excluded(in->exclude, f[i].name)) {
      if (!restartable_only) say(note, note_ctx, "%s: left out (--exclude)%s", f[i].name, "");
      continue;
    }
    char why[512] = "";
    if (f[i].applies && !f[i].applies(in, why, sizeof why)) {
      if (!restartable_only) say(note, note_ctx, "%s: not fitted: %s", f[i].name, why);   /* said once */
      continue;
    }
    sf_candidate c;
    sf_error ferr = {0};
    if (f[i].make(in, &c, &ferr) != SF_OK) {
      if (ferr.status != SF_ERR_INPUT) {
        *err = ferr;
        return err->status;
      }
      say(note, note_ctx, "%s: fit failed, skipped: %s", f[i].name, ferr.message);
      continue;
    }
    if (add(list, &c, err) != SF_OK) return err->status;
    if (n_added) ++*n_added;
  }
  return SF_OK;
}

/* "<name>-<n>" with n a restart's number: 2, 3, ... (no sign, no leading 0). */
static int restart_of(const char *stem, size_t stem_len, const char *name) {
  size_t n = strlen(name);
  if (stem_len < n + 2 || strncmp(stem, name, n) != 0 || stem[n] != '-') return 0;
  if (stem[n + 1] < '1' || stem[n + 1] > '9') return 0;
  for (size_t k = n + 1; k < stem_len; ++k)
    if (stem[k] < '0' || stem[k] > '9') return 0;
  return 1;
}

int sf_candidate_network_name(const char *name, size_t len) {
  const sf_candidate_factory *f;
  int n = sf_candidate_factories(&f);
  for (int i = 0; i < n; ++i) {
    if (!f[i].restartable) continue;
    if (len == strlen(f[i].name) && strncmp(name, f[i].name, len) == 0) return 1;
    if (restart_of(name, len, f[i].name)) return 1;
  }
  return 0;
}

/* The analytic baselines --exclude takes (the fitted models: factories). */
static const char *const excludable_baselines[] = {"chapman",   "taylor",         "flat",     "spline",
                                                   "naive-sky", "raymarched-sky", "flat-sky", "schuler-sky"};
#define N_EXCLUDABLE_BASELINES (sizeof excludable_baselines / sizeof excludable_baselines[0])

static int excludable(const char *name, size_t len) {
  for (size_t k = 0; k < N_EXCLUDABLE_BASELINES; ++k)
    if (strlen(excludable_baselines[k]) == len && strncmp(name, excludable_baselines[k], len) == 0) return 1;
  const sf_candidate_factory *f;
  int n = sf_candidate_factories(&f);
  for (int i = 0; i < n; ++i)
    if (strlen(f[i].name) == len && strncmp(name, f[i].name, len) == 0) return 1;
  return 0;
}

int sf_candidate_exclude_check(const char *list, char *why, size_t why_len) {
  for (const char *p = list; *p;) {
    size_t len = strcspn(p, ",");
    if (len > 0 && !excludable(p, len)) {
      char known[512] = "";
      const sf_candidate_factory *f;
      int n = sf_candidate_factories(&f);
      for (size_t k = 0; k < N_EXCLUDABLE_BASELINES + (size_t)n; ++k) {
        size_t used = strlen(known);
        snprintf(known + used, sizeof known - used, "%s%s", k ? ", " : "",
                 k < N_EXCLUDABLE_BASELINES ? excludable_baselines[k] : f[k - N_EXCLUDABLE_BASELINES].name);
      }
      snprintf(why, why_len, "'%.*s' is not a model a build can leave out (%s; the references, the table lookups "
               "and naive16, the cost unit, stay)", (int)len, p, known);
      return -1;
    }
    p += len;
    if (*p == ',') ++p;
  }
  return 0;
}

int sf_candidate_excluded(const char *list, const char *name) {
  if (!list) return 0;
  for (const char *p = list; *p;) {
    size_t len = strcspn(p, ",");
    char entry[64];
    if (len > 0 && len < sizeof entry) {
      memcpy(entry, p, len);
      entry[len] = '\0';
      if (strcmp(name, entry) == 0 || restart_of(name, strlen(name), entry)) return 1;
    }
    p += len;
    if (*p == ',') ++p;
  }
  return 0;
}

/* Adds c, or frees it where --exclude names it (said once). */
static int add_unless_excluded(const sf_candidate_inputs *in, sf_candidate_list *list, sf_candidate *c,
                               sf_candidate_note_fn note, void *note_ctx, sf_error *err) {
  if (!sf_candidate_excluded(in->exclude, c->name)) return add(list, c, err);
  say(note, note_ctx, "%s: left out (--exclude)%s", c->name, "");
  sf_candidate_free(c);
  return SF_OK;
}

int sf_candidates_make_all(const sf_candidate_inputs *in, sf_candidate_list *list, sf_candidate_note_fn note,
                           void *note_ctx, sf_error *err) {
  /* the fits' cache and weights folders first: their failures are the
   * build's, not fits to skip (make_fitted) */
  if (in->cache_dir) {
    char fits[4200];
    snprintf(fits, sizeof fits, "%s/%s", in->cache_dir, SF_CACHE_FITS);
    if (sf_make_folders(fits, "cache", err) != SF_OK || sf_folder_writable(fits, "cache", err) != SF_OK)
      return err->status;
  }
  if (in->work_dir && sf_folder_writable(in->work_dir, "weights", err) != SF_OK) return err->status;
  sf_candidate c;
  if (sf_candidate_reference_transmittance(in->atm, &c, err) != SF_OK || add(list, &c, err) != SF_OK)
    return err->status;
  if ((in->scene->quantities & SF_QUANTITY_TRANSMITTANCE) && in->sky &&
      sf_candidate_table_transmittance(in->sky, &c, err) == SF_OK && add(list, &c, err) != SF_OK)
    return err->status;
  /* naive16 always: it is the cost unit of SPEC §12. The other
   * transmittance models only when the scene asks for transmittance. */
  int want_transmittance = (in->scene->quantities & SF_QUANTITY_TRANSMITTANCE) != 0;
  static const sf_transmittance_baseline kinds[] = {SF_TB_NAIVE, SF_TB_CHAPMAN, SF_TB_TAYLOR, SF_TB_FLAT,
                                                    SF_TB_SPLINE};
  size_t n_kinds = want_transmittance ? sizeof kinds / sizeof kinds[0] : 1;
  for (size_t k = 0; k < n_kinds; ++k) {
    sf_error why = {0};
    if (sf_candidate_transmittance_baseline(in->atm, kinds[k], SF_NAIVE_COST_UNIT_STEPS, &c, &why) == SF_OK) {
      if (add_unless_excluded(in, list, &c, note, note_ctx, err) != SF_OK) return err->status;
    } else if (why.status == SF_ERR_INPUT) {
      say(note, note_ctx, "baseline skipped: %s%s", why.message, "");
    } else {
      *err = why;
      return err->status;
    }
  }
  int want_radiance = (in->scene->quantities & SF_QUANTITY_SKY_RADIANCE) && in->sky;
  if (want_radiance) {
    if (sf_candidate_table_sky_radiance(in->sky, &c, err) != SF_OK || add(list, &c, err) != SF_OK)
      return err->status;
    /* the single-scattering skies, from the atmosphere alone */
    static int (*const skies[])(const sf_atmosphere *, sf_candidate *, sf_error *) = {
        sf_candidate_sky_naive, sf_candidate_sky_raymarched, sf_candidate_sky_flat, sf_candidate_sky_schuler};
    for (size_t k = 0; sf_atmosphere_scattering_count(in->atm) > 0 && k < sizeof skies / sizeof skies[0]; ++k)
      if (skies[k](in->atm, &c, err) != SF_OK || add_unless_excluded(in, list, &c, note, note_ctx, err) != SF_OK)
        return err->status;
  }
  for (int q = 0; q < SF_CANDIDATE_N_QUANTITIES; ++q) {
    if (q == SF_CANDIDATE_SKY_RADIANCE && !want_radiance) continue;
    if (q == SF_CANDIDATE_TRANSMITTANCE && !want_transmittance) continue;
    if (make_fitted(in, (sf_candidate_quantity)q, 0, list, NULL, note, note_ctx, err) != SF_OK) return err->status;
  }
  return SF_OK;
}

int sf_candidates_make_restart(const sf_candidate_inputs *in, sf_candidate_quantity q, sf_candidate_list *list,
                               int *n_added, sf_candidate_note_fn note, void *note_ctx, sf_error *err) {
  *n_added = 0;
  return make_fitted(in, q, 1, list, n_added, note, note_ctx, err);
}
