/* sf_report_evaluate: errors over the domain, cost, the selection, the
 * segments' errors and the standard views (see codegen/report.h). */
#include "codegen/report.h"
#include "codegen/report_views.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include <cjson/cJSON.h>

#include "fit/candidate_cache.h"
#include "models/atmosphere_file.h"
#include "models/views_standard.h"
#include "util/atomic_file.h"
#include "util/cache_prune.h"

void sf_report_options_default(sf_report_options *o) {
  memset(o, 0, sizeof *o);
  o->domain_samples = 20000;
  o->timing_points = 1000000;
  o->timing_repetitions = 3;
  o->view_width = SF_VIEW_DEFAULT_WIDTH;
  o->view_height = SF_VIEW_DEFAULT_HEIGHT;
  o->render_views = 1;
  o->seed = 1;
}

static void progress(const sf_report_options *o, const char *stage, double f) {
  if (o->run.progress) o->run.progress(o->run.progress_ctx, stage, f);
}

static int contains_domain(const sf_scene_domain *valid, const sf_scene_domain *d) {
  const double e = 1e-9;
  return valid->h_min_km <= d->h_min_km + e && valid->h_max_km >= d->h_max_km - e &&
         valid->mu_min <= d->mu_min + e && valid->mu_max >= d->mu_max - e &&
         valid->mu_s_min <= d->mu_s_min + e && valid->mu_s_max >= d->mu_s_max - e;
}

/* ---- errors over the domain ---- */

/* The part of the scene's domain where c is valid; 0 if empty. */
static int valid_part(const sf_scene_domain *d, const sf_scene_domain *v, sf_scene_domain *out) {
  out->h_min_km = fmax(d->h_min_km, v->h_min_km);
  out->h_max_km = fmin(d->h_max_km, v->h_max_km);
  out->mu_min = fmax(d->mu_min, v->mu_min);
  out->mu_max = fmin(d->mu_max, v->mu_max);
  out->mu_s_min = fmax(d->mu_s_min, v->mu_s_min);
  out->mu_s_max = fmin(d->mu_s_max, v->mu_s_max);
  return out->h_min_km <= out->h_max_km && out->mu_min <= out->mu_max && out->mu_s_min <= out->mu_s_max;
}

/* The errors of the candidates of quantity q that are measured on box d
 * (partial = 0: those valid over the whole domain, on the domain itself;
 * partial = 1: candidate only, on its valid part). */
static int errors_on(sf_report *rep, const sf_candidate_list *list, sf_candidate_quantity q, const sf_scene_domain *d,
                     int only, const sf_report_options *o, sf_error *err) {
  const sf_candidate *ref = &list->items[rep->reference[q]];
  sf_domain_samples s;
  if (sf_domain_samples_make(d, q, o->domain_samples, o->seed, &s, err) != SF_OK) return err->status;
  size_t nv = s.n * (size_t)ref->n_channels;
  double *truth = malloc(sizeof(double) * nv), *model = malloc(sizeof(double) * nv);
  if (!truth || !model) {
    free(truth); free(model); sf_domain_samples_free(&s);
    return sf_fail(err, SF_ERR_INTERNAL, "out of memory");
  }
  sf_candidate_values(ref, &s, truth, &o->run);
  int status = SF_OK;
  for (int i = 0; i < rep->n_models; ++i) {
    sf_report_model *m = &rep->models[i];
    const sf_candidate *c = m->candidate;
    if (c->quantity != q || c->role == SF_ROLE_REFERENCE) continue;
    if (only >= 0 ? i != only : m->errors_over_valid_part) continue;
    progress(o, q == SF_CANDIDATE_TRANSMITTANCE ? "errors (transmittance)" : "errors (sky radiance)",
             (double)i / rep->n_models);
    if (c->n_channels != ref->n_channels) {
      status = sf_fail(err, SF_ERR_INTERNAL, "%s has %d channels, the reference %d", c->name, c->n_channels,
                       ref->n_channels);
      break;
    }
    sf_candidate_values(c, &s, model, &o->run);
    sf_error_metrics_compute(model, truth, nv, &m->errors, &m->non_finite);
    m->errors_domain = *d;
    m->has_errors = 1;
  }
  free(truth); free(model);
  sf_domain_samples_free(&s);
  return status;
}

static int measure_errors(sf_report *rep, const sf_candidate_list *list, sf_candidate_quantity q,
                          const sf_report_options *o, sf_error *err) {
  for (int i = 0; i < rep->n_models; ++i) {
    sf_report_model *m = &rep->models[i];
    if (m->candidate->quantity != q || m->candidate->role == SF_ROLE_REFERENCE || m->valid_over_domain) continue;
    m->errors_over_valid_part = valid_part(&rep->domain, &m->candidate->valid, &m->errors_domain);
  }
  if (errors_on(rep, list, q, &rep->domain, -1, o, err) != SF_OK) return err->status;
  for (int i = 0; i < rep->n_models; ++i) {
    sf_report_model *m = &rep->models[i];
    if (m->candidate->quantity != q || !m->errors_over_valid_part) continue;
    sf_scene_domain part = m->errors_domain;
    if (errors_on(rep, list, q, &part, i, o, err) != SF_OK) return err->status;
  }
  return SF_OK;
}

/* ---- cost ---- */

/* The cost cache (fit/candidate_cache.h): a candidate's timing keyed by
 * what it evaluates and how it is timed, so that a rerun with nothing
 * changed reports the same figures without timing again. */
static int cost_cache_path(const sf_report *rep, const sf_candidate *c, const sf_scene_domain *timed_on,
                           int precision_bits, const sf_report_options *o, char *path, size_t n, sf_error *err) {
  path[0] = '\0';
  if (!o->cost_cache_dir) return SF_OK;
  sf_cache_key k;
  k.text[0] = '\0';
  char code[256];
  sf_cache_code_identity(code, sizeof code);
  sf_cache_key_add_text(&k, "code", code);
  /* timings are the machine's: an output folder copied with its cache to
   * another had reported the first machine's */
  char machine[256];
  sf_cache_machine_identity(machine, sizeof machine);
  sf_cache_key_add_text(&k, "machine", machine);
  sf_cache_key_add_text(&k, "candidate", c->name);
  sf_cache_key_add_text(&k, "quantity", sf_candidate_quantity_name(c->quantity));
  sf_cache_key_add_text(&k, "label", c->label);
  sf_cache_key_add_text(&k, "description", c->description);
  sf_cache_key_add_text(&k, "atmosphere", rep->atmosphere_hash);
  sf_cache_key_add_number(&k, "channels", c->n_channels);
  sf_cache_key_add_number(&k, "params", (double)c->n_params);
  sf_cache_key_add_number(&k, "bytes", (double)c->constant_bytes);
  sf_cache_key_add_number(&k, "precision", precision_bits);
  sf_cache_key_add_number(&k, "h_min", timed_on->h_min_km);
  sf_cache_key_add_number(&k, "h_max", timed_on->h_max_km);
  sf_cache_key_add_number(&k, "mu_min", timed_on->mu_min);
  sf_cache_key_add_number(&k, "mu_max", timed_on->mu_max);
  sf_cache_key_add_number(&k, "mu_s_min", timed_on->mu_s_min);
  sf_cache_key_add_number(&k, "mu_s_max", timed_on->mu_s_max);
  sf_cache_key_add_number(&k, "points", (double)o->timing_points);
  sf_cache_key_add_number(&k, "repetitions", o->timing_repetitions);
  sf_cache_key_add_number(&k, "seed", (double)o->seed);
  return sf_cache_path(o->cost_cache_dir, SF_CACHE_COSTS, c->name, &k, path, n, err);
}

/* A cached timing and the run that measured it ("" when unusable). */
static int cost_cache_read(const char *path, sf_cost *out, char *run, size_t run_size) {
  run[0] = '\0';
  if (!path[0] || !sf_cache_exists(path)) return 0;
  FILE *f = fopen(path, "rb");
  if (!f) return 0;
  char text[1024];
  size_t got = fread(text, 1, sizeof text - 1, f);
  fclose(f);
  text[got] = '\0';
  cJSON *doc = cJSON_Parse(text);
  static const char *const keys[] = {"ns_median", "ns_min", "ns_max", "repetitions", "n_points", "precision_bits"};
  double v[6];
  int ok = doc != NULL;
  for (int i = 0; i < 6 && ok; ++i) {
    const cJSON *item = cJSON_GetObjectItemCaseSensitive(doc, keys[i]);
    ok = cJSON_IsNumber(item) && isfinite(item->valuedouble) && item->valuedouble >= 0.0;
    if (ok) v[i] = item->valuedouble;
  }
  const cJSON *id = doc ? cJSON_GetObjectItemCaseSensitive(doc, "run") : NULL;
  ok = ok && cJSON_IsString(id) && id->valuestring[0] && strlen(id->valuestring) < run_size;
  if (ok) snprintf(run, run_size, "%s", id->valuestring);
  cJSON_Delete(doc);
  /* unusable (damaged, edited): time again */
  if (!ok || !(v[0] > 0.0) || !(v[1] <= v[0] && v[0] <= v[2]) || (v[5] != 32.0 && v[5] != 64.0)) return 0;
  out->ns_median = v[0];
  out->ns_min = v[1];
  out->ns_max = v[2];
  out->repetitions = (int)v[3];
  out->n_points = (size_t)v[4];
  out->precision_bits = (int)v[5];
  return 1;
}

static int cost_cache_write(const char *path, const sf_cost *c, const char *run, sf_error *err) {
  if (!path[0]) return SF_OK;
  sf_atomic_file f;
  if (sf_atomic_open(&f, path, err) != SF_OK) return err->status;
  fprintf(f.stream,
          "{\"ns_median\": %.17g, \"ns_min\": %.17g, \"ns_max\": %.17g, \"repetitions\": %d, "
          "\"n_points\": %zu, \"precision_bits\": %d, \"run\": \"%s\"}\n",
          c->ns_median, c->ns_min, c->ns_max, c->repetitions, c->n_points, c->precision_bits, run);
  return sf_atomic_commit(&f, err);
}

/* What is timed: the naive raymarch in double (the unit of a candidate
 * timed in double), then every candidate but the references. */
typedef struct timed {
  const sf_candidate *candidate;
  sf_candidate as_double;   /* the naive raymarch's double twin */
  sf_cost *cost;
  sf_cost naive_f64;
  char path[4400];
  const sf_scene_domain *on;     /* the inputs it is timed on */
  const sf_domain_samples *samples;
  sf_domain_samples *own;        /* samples made for it (its valid part), or NULL */
} timed;

static int measure_costs(sf_report *rep, const sf_report_options *o, sf_error *err) {
  sf_domain_samples s[SF_CANDIDATE_N_QUANTITIES];
  memset(s, 0, sizeof s);
  int status = SF_OK;
  for (int q = 0; q < SF_CANDIDATE_N_QUANTITIES && status == SF_OK; ++q)
    status = sf_domain_samples_make(&rep->domain, (sf_candidate_quantity)q, o->timing_points, o->seed + 1, &s[q], err);
  int naive = -1;
  for (int i = 0; i < rep->n_models; ++i)
    if (rep->models[i].candidate->quantity == SF_CANDIDATE_TRANSMITTANCE &&
        strcmp(rep->models[i].candidate->name, "naive16") == 0)
      naive = i;
  timed *jobs = calloc((size_t)rep->n_models + 1, sizeof *jobs);
  if (!jobs) status = sf_fail(err, SF_ERR_INTERNAL, "out of memory");
  int n = 0;
  sf_cost naive_f64 = {0};
  if (status == SF_OK && naive >= 0) {
    jobs[n].as_double = *rep->models[naive].candidate;
    jobs[n].as_double.eval_f32 = NULL;
    jobs[n].candidate = &jobs[n].as_double;
    jobs[n].cost = &naive_f64;
    jobs[n].on = &rep->domain;
    jobs[n].samples = &s[SF_CANDIDATE_TRANSMITTANCE];
    ++n;
  }
  for (int i = 0; i < rep->n_models && status == SF_OK; ++i) {
    sf_report_model *m = &rep->models[i];
    if (m->candidate->role == SF_ROLE_REFERENCE) continue;
    jobs[n].candidate = m->candidate;
    jobs[n].cost = &m->cost;
    jobs[n].on = &rep->domain;
    jobs[n].samples = &s[m->candidate->quantity];
    /* A model valid on part of the domain (Preetham, Hosek: a viewer on the
     * ground, the sun up) is timed where its errors are measured: on the
     * whole scene's inputs it had run 15 % off its cost where it is used. */
    if (m->errors_over_valid_part) {
      sf_domain_samples *own = malloc(sizeof *own);
      if (!own) status = sf_fail(err, SF_ERR_INTERNAL, "out of memory");
      else if ((status = sf_domain_samples_make(&m->errors_domain, m->candidate->quantity, o->timing_points,
                                                o->seed + 1, own, err)) != SF_OK)
        free(own);
      else {
        jobs[n].on = &m->errors_domain;
        jobs[n].samples = jobs[n].own = own;
      }
    }
    ++n;
  }
  /* SPEC §12's ratios are of timings taken in one run: the cache serves
   * them only if it holds every one, all from the same run; otherwise all
   * are timed now (a cached naive raymarch beside a freshly timed network
   * had mixed two runs). */
  char first_run[64] = "", run[64];
  int all_cached = status == SF_OK && o->cost_cache_dir != NULL;
  for (int j = 0; j < n && status == SF_OK; ++j) {
    const sf_candidate *c = jobs[j].candidate;
    status = cost_cache_path(rep, c, jobs[j].on, c->eval_f32 ? 32 : 64, o, jobs[j].path, sizeof jobs[j].path, err);
    if (status != SF_OK || !all_cached) continue;
    if (!cost_cache_read(jobs[j].path, jobs[j].cost, run, sizeof run) || (j > 0 && strcmp(run, first_run) != 0))
      all_cached = 0;
    else if (j == 0)
      snprintf(first_run, sizeof first_run, "%s", run);
  }
  if (status == SF_OK && all_cached && n > 0) {
    for (int j = 0; j < n; ++j) sf_cache_entry_used(jobs[j].path);
  } else if (status == SF_OK) {
    struct timespec now;
    clock_gettime(CLOCK_REALTIME, &now);
    snprintf(run, sizeof run, "%lld.%09ld.%ld", (long long)now.tv_sec, now.tv_nsec, (long)getpid());
    /* Round robin: each round times every model once, the naive
     * raymarch among them, so that a slow spell of the machine lands on
     * all of them alike. Timed one after the other (the naive raymarch
     * once, first), a run's ratios had moved by up to 1.4x (an audit: four
     * builds of one scene), more than the 10 % of the selection's tie. */
    int rounds = o->timing_repetitions;
    double *ns = rounds >= 1 && rounds <= 1000 ? malloc(sizeof *ns * (size_t)n * (size_t)rounds) : NULL;
    if (!(rounds >= 1 && rounds <= 1000)) status = sf_fail(err, SF_ERR_INPUT, "repetitions must be in 1..1000");
    else if (!ns) status = sf_fail(err, SF_ERR_INTERNAL, "out of memory");
    for (int r = 0; r < rounds && status == SF_OK; ++r)
      for (int j = 0; j < n && status == SF_OK; ++j) {
        progress(o, "timing (1 thread)", (double)(r * n + j) / ((double)rounds * n));
        status = sf_candidate_time_pass(jobs[j].candidate, jobs[j].samples, &ns[(size_t)j * rounds + r], err);
      }
    for (int j = 0; j < n && status == SF_OK; ++j) {
      sf_cost_from_passes(jobs[j].candidate, jobs[j].samples, &ns[(size_t)j * rounds], rounds, jobs[j].cost);
      status = cost_cache_write(jobs[j].path, jobs[j].cost, run, err);
    }
    free(ns);
  }
  for (int j = 0; j < n; ++j)
    if (jobs[j].own) {
      sf_domain_samples_free(jobs[j].own);
      free(jobs[j].own);
    }
  free(jobs);
  if (status == SF_OK && naive >= 0) {
    rep->naive16_ns_f64 = naive_f64.ns_median;
    rep->naive16_ns_f32 = rep->models[naive].cost.ns_median;
  }
  for (int i = 0; i < rep->n_models && status == SF_OK; ++i) {
    sf_report_model *m = &rep->models[i];
    if (m->candidate->role == SF_ROLE_REFERENCE) continue;
    m->has_cost = 1;
    double unit = m->cost.precision_bits == 32 ? rep->naive16_ns_f32 : rep->naive16_ns_f64;
    m->cost_ratio_naive16 = unit > 0.0 ? m->cost.ns_median / unit : 0.0;
  }
  for (int q = 0; q < SF_CANDIDATE_N_QUANTITIES; ++q) sf_domain_samples_free(&s[q]);
  return status;
}

int sf_report_evaluate(sf_report *rep, const sf_scene *scene, const sf_candidate_list *list,
                       const sf_report_options *opt, const char *out_dir, sf_error *err) {
  memset(rep, 0, sizeof *rep);
  rep->options = *opt;
  snprintf(rep->out_dir, sizeof rep->out_dir, "%s", out_dir);
  snprintf(rep->scene_name, sizeof rep->scene_name, "%s", scene->name);
  snprintf(rep->atmosphere_name, sizeof rep->atmosphere_name, "%s", scene->atmosphere.name);
  sf_atmosphere_hash_hex(&scene->atmosphere, rep->atmosphere_hash);
  rep->quantities = scene->quantities;
  rep->n_channels = scene->atmosphere.n_channels;
  if (sf_scene_get_domain(scene, &rep->domain, err) != SF_OK) return err->status;
  rep->models = calloc((size_t)(list->count > 0 ? list->count : 1), sizeof *rep->models);
  if (!rep->models) return sf_fail(err, SF_ERR_INTERNAL, "out of memory");
  rep->n_models = list->count;
  rep->reference[0] = rep->reference[1] = -1;
  for (int i = 0; i < list->count; ++i) {
    const sf_candidate *c = &list->items[i];
    rep->models[i].candidate = c;
    rep->models[i].valid_over_domain = contains_domain(&c->valid, &rep->domain);
    if (c->role == SF_ROLE_REFERENCE) {
      if (rep->reference[c->quantity] >= 0)
        return sf_fail(err, SF_ERR_INTERNAL, "two references for %s", sf_candidate_quantity_name(c->quantity));
      rep->reference[c->quantity] = i;
    } else if (rep->reference[c->quantity] < 0) {
      return sf_fail(err, SF_ERR_INTERNAL, "candidate %s is listed before its reference", c->name);
    }
  }
  int status = SF_OK;
  for (int q = 0; q < SF_CANDIDATE_N_QUANTITIES && status == SF_OK; ++q)
    if (rep->reference[q] >= 0) status = measure_errors(rep, list, (sf_candidate_quantity)q, opt, err);
  if (status == SF_OK && opt->timing_points > 0) status = measure_costs(rep, opt, err);
  /* The segments after the selection, which needs every whole ray's error
   * and cost: a sky network's segment (eq. 44) takes the transmittance
   * network the header emits beside it, the selected one where the
   * selection is a network (sf_report_transmittance_partner). Measured
   * before it, they had taken the most accurate network, and a build that
   * selected a cheaper restart shipped another than the report measured. */
  if (status == SF_OK) sf_report_select(rep, scene);
  for (int q = 0; q < SF_CANDIDATE_N_QUANTITIES && status == SF_OK; ++q) {
    progress(opt, "errors (segments)", (double)q / SF_CANDIDATE_N_QUANTITIES);
    status = sf_report_measure_segments(rep, list, (sf_candidate_quantity)q, scene->atmosphere.bottom_radius_km,
                                        scene->atmosphere.top_radius_km, opt, err);
  }
  if (status == SF_OK && opt->render_views) {
    /* The pictures are linear sRGB: an atmosphere of wavelengths (even 3
     * of them, whose first, 440 nm, would be drawn red) has none. */
    if (!scene->atmosphere.spectral && rep->n_channels == 3) {
      status = sf_report_render_views(rep, scene, opt, err);
      rep->views_rendered = status == SF_OK;
    } else {
      snprintf(rep->views_note, sizeof rep->views_note,
               "The standard views are rendered for RGB atmospheres only; this one has %d %s.", rep->n_channels,
               scene->atmosphere.spectral ? "wavelengths" : "channels");
    }
  }
  return status;
}

void sf_report_mean_rel_note(const sf_report_model *m, char *buf, size_t n) {
  buf[0] = '\0';
  const sf_error_metrics *e = &m->errors;
  if (!m->has_errors || e->n_values == 0 || !(e->mean_rel_floor_share > SF_METRICS_FLOOR_SHARE_NOTE)) return;
  snprintf(buf, n,
           "%s's mean rel (%.3g) is mostly near-zero references: %.0f %% of its values have a reference below the "
           "floor (1e-3 of the reference's RMS) and make %.0f %% of it, a small absolute error there being a large "
           "relative one; its rel RMSE (%.3g) is the figure to compare.",
           m->candidate->name, e->mean_rel, 100.0 * (double)e->n_below_floor / (double)e->n_values,
           100.0 * e->mean_rel_floor_share, e->rel_rmse);
}

void sf_report_free(sf_report *rep) {
  free(rep->models);
  rep->models = NULL;
  rep->n_models = 0;
}
