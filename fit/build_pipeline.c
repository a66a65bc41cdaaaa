#include "fit/build_pipeline.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "codegen/codegen_file.h"
#include "codegen/emit_selection_alias.h"
#include "codegen/report_views.h"
#include "data/sky_lookup.h"
#include "data/sky_table_check.h"
#include "fit/candidate_metrics.h"
#include "fit/build_pipeline_spectral4.h"
#include "fit/build_stale_weights.h"
#include "fit/build_weights_errors.h"
#include "fit/build_staging.h"
#include "fit/output_norm.h"
#include "codegen/fitted_part.h"
#include "models/weights_file.h"
#include "fit/candidate_fitted.h"
#include "models/atmosphere_file.h"
#include "data/phase_peak.h"
#include "util/make_folders.h"
#include "util/path_from_folder.h"
#include "util/clock.h"
#include "util/signal_defer.h"

void sf_build_options_default(sf_build_options *o) {
  memset(o, 0, sizeof *o);
  sf_table_set_options_default(&o->tables);
  sf_report_options_default(&o->report);
  o->emit = 1;
  o->cache_limit_bytes = SF_CACHE_LIMIT_DEFAULT_BYTES;
  /* the sky network brightness-normalised (fit/output_norm.h): lower view
   * errors in every seed measured, dawn several times lower (README) */
  o->mlp_scattering_normalise = 1;
  o->mlp_scattering_normalise_cap = SF_OUTPUT_NORM_CAP_BELOW;
}

/* The scene's outputs (SPEC §5), exactly as named, or OUT/sky.h and
 * OUT/sky.glsl. */
int sf_build_header_paths(const sf_scene *scene, const sf_build_options *o, char *c_path, char *glsl_path, size_t n,
                          sf_error *err) {
  int c = o->header_c           ? snprintf(c_path, n, "%s", o->header_c)
          : scene->output_c[0] ? snprintf(c_path, n, "%s", scene->output_c)
                               : snprintf(c_path, n, "%s/sky.h", o->out_dir);
  int g = o->header_glsl           ? snprintf(glsl_path, n, "%s", o->header_glsl)
          : scene->output_glsl[0] ? snprintf(glsl_path, n, "%s", scene->output_glsl)
                                  : snprintf(glsl_path, n, "%s/sky.glsl", o->out_dir);
  if (c < 0 || (size_t)c >= n) return sf_fail(err, SF_ERR_INPUT, "%s: output path too long", c_path);
  if (g < 0 || (size_t)g >= n) return sf_fail(err, SF_ERR_INPUT, "%s: output path too long", glsl_path);
  return SF_OK;
}

/* The largest error the fit itself found (its weights file's
 * metrics.max_abs), or NAN: none, or no weights file. */
static double fit_max_abs(const sf_candidate *c) {
  if (!c->weights_path[0]) return NAN;
  sf_weights w;
  sf_error err = {0};
  if (sf_weights_load_file(c->weights_path, NULL, &w, &err) != SF_OK) return NAN;
  double v = sf_weights_metric(&w, "max_abs");
  sf_weights_free(&w);
  return v;
}

/* The emitted part of report model m for quantity q. */
static void model_part(const sf_report *rep, const sf_scene *scene, const sf_report_model *m,
                       sf_candidate_quantity q, sf_codegen_part *p) {
  const sf_candidate *c = m->candidate;
  memset(p, 0, sizeof *p);
  snprintf(p->name, sizeof p->name, "%s", c->emit_name);
  snprintf(p->quantity, sizeof p->quantity, "%s", sf_candidate_quantity_name(q));
  snprintf(p->summary, sizeof p->summary, "%s: %s", c->label, c->description);
  snprintf(p->atmosphere_name, sizeof p->atmosphere_name, "%s", scene->atmosphere.name);
  snprintf(p->atmosphere_hash, sizeof p->atmosphere_hash, "%s", rep->atmosphere_hash);
  p->domain = rep->domain;
  p->viewer_max_km = scene->viewer_altitude_km[1];
  char max_text[128];
  sf_fitted_max_abs_text(m->errors.max_abs, fit_max_abs(c), max_text, sizeof max_text);
  snprintf(p->error, sizeof p->error, "RMSE %.3g, %s, mean rel %.3g, rel RMSE %.3g over %zu in-domain values%s",
           m->errors.rmse, max_text, m->errors.mean_rel, m->errors.rel_rmse, m->errors.n_values,
           m->meets_budget ? "" : " (does NOT meet the scene's budget)");
  p->emit = c->emit;
  p->model = c->emit_model;
}

/* The selected models' headers, written to temporaries beside their paths
 * (headers: committed with the other outputs, fit/build_staging.h). */
static int emit_selection(sf_report *rep, const sf_scene *scene, const sf_build_options *o, sf_build_result *res,
                          sf_codegen_files *headers, sf_error *err) {
  sf_codegen_part parts[SF_CANDIDATE_N_QUANTITIES + 3];
  int n = 0;
  int part_of[SF_CANDIDATE_N_QUANTITIES] = {-1, -1};   /* the selected model's part per quantity */
  sf_selection_alias alias;
  memset(&alias, 0, sizeof alias);
  alias.n_channels = scene->atmosphere.n_channels;
  for (int q = 0; q < SF_CANDIDATE_N_QUANTITIES; ++q) {
    sf_report_selection *s = &rep->selection[q];
    if (!s->asked || s->model < 0) continue;
    const sf_report_model *m = &rep->models[s->model];
    const sf_candidate *c = m->candidate;
    if (!c->emit) {
      snprintf(s->emit_note, sizeof s->emit_note, "No code emitter exists for %s yet; nothing emitted for %s.",
               c->name, sf_candidate_quantity_name((sf_candidate_quantity)q));
      continue;
    }
    part_of[q] = n;
    model_part(rep, scene, m, (sf_candidate_quantity)q, &parts[n++]);
    if (q == SF_CANDIDATE_TRANSMITTANCE) {
      snprintf(alias.transmittance, sizeof alias.transmittance, "%s", c->emit_name);
    } else {
      snprintf(alias.sky_radiance, sizeof alias.sky_radiance, "%s", c->emit_name);
      alias.sky_takes_altitude = !c->emit_ground_viewer;
    }
  }
  /* The sky network's segment function (eq. 44) takes the transmittance
   * network's, the one the report's sky segments took
   * (sf_report_transmittance_partner): the selected transmittance model
   * when it is a network; otherwise a network is emitted beside it for the
   * segments, so renderers keep calling skyfit_sky_radiance_segment
   * whatever the transmittance selection. A build without a transmittance
   * network (a scene that does not ask for transmittance) emits no
   * segment, and its report says so. */
  int sky_network = strcmp(alias.sky_radiance, "mlp") == 0;
  int t_part = -1;
  if (sky_network) {
    int k = sf_report_transmittance_partner(rep, "mlp");
    if (k >= 0 && k == rep->selection[SF_CANDIDATE_TRANSMITTANCE].model) {
      t_part = part_of[SF_CANDIDATE_TRANSMITTANCE];
    } else if (k >= 0) {
      t_part = n;
      model_part(rep, scene, &rep->models[k], SF_CANDIDATE_TRANSMITTANCE, &parts[n++]);
      size_t len = strlen(parts[t_part].summary);
      snprintf(parts[t_part].summary + len, sizeof parts[t_part].summary - len,
               " (not selected: emitted for the sky network's segments)");
      /* the report names what ships, not only what was selected */
      sf_report_selection *s = &rep->selection[SF_CANDIDATE_SKY_RADIANCE];
      snprintf(s->emit_note, sizeof s->emit_note,
               "skyfit_sky_radiance_segment (eq. 44) takes the transmittance of %s, emitted for it though not "
               "selected; the sky segment columns were measured with it.",
               rep->models[k].candidate->name);
    } else {
      sf_report_selection *s = &rep->selection[SF_CANDIDATE_SKY_RADIANCE];
      snprintf(s->emit_note, sizeof s->emit_note,
               "No transmittance network is among this build's models, so skyfit_sky_radiance_segment "
               "(eq. 44, which takes its transmittance) is not emitted.");
    }
  }
  alias.sky_has_segment = sky_network && t_part >= 0;
  if (!sky_network && alias.sky_radiance[0]) {
    /* the single-scattering and fitted skies are of whole rays only */
    sf_report_selection *s = &rep->selection[SF_CANDIDATE_SKY_RADIANCE];
    snprintf(s->emit_note, sizeof s->emit_note,
             "The selected sky model (%s) gives whole rays only, so skyfit_sky_radiance_segment (aerial "
             "perspective) is not emitted; the sky network has one.", alias.sky_radiance);
  }
  /* Two networks both emit skyfit_mlp_* functions: one part holds both. */
  sf_mlp_emit_pair pair;
  if (alias.sky_has_segment) {
    int s_part = part_of[SF_CANDIDATE_SKY_RADIANCE];
    sf_codegen_part *t = &parts[t_part], *sky = &parts[s_part];
    pair.transmittance = t->model;
    pair.scattering = sky->model;
    t->emit = sf_candidate_emit_mlp_pair;
    t->model = &pair;
    snprintf(t->quantity, sizeof t->quantity, "transmittance, sky_radiance");
    char summary[SF_CODEGEN_TEXT_LEN], error[SF_CODEGEN_TEXT_LEN];
    snprintf(summary, sizeof summary, "%.500s | %.500s", t->summary, sky->summary);
    snprintf(error, sizeof error, "transmittance: %.480s | sky radiance: %.480s", t->error, sky->error);
    snprintf(t->summary, sizeof t->summary, "%s", summary);
    snprintf(t->error, sizeof t->error, "%s", error);
    memmove(&parts[s_part], &parts[s_part + 1], (size_t)(n - s_part - 1) * sizeof parts[0]);
    --n;
  }
  if (n > 0) {   /* the stable names (codegen/emit_selection_alias.h) */
    sf_codegen_part *p = &parts[n++];
    memset(p, 0, sizeof *p);
    snprintf(p->name, sizeof p->name, "selection");
    snprintf(p->quantity, sizeof p->quantity, "stable names");
    snprintf(p->summary, sizeof p->summary, "skyfit_transmittance%s / skyfit_sky_radiance%s call the selected models%s%s%s%s",
             alias.transmittance[0] ? "" : " (none)", alias.sky_radiance[0] ? "" : " (none)",
             alias.transmittance[0] ? ": transmittance " : "", alias.transmittance,
             alias.sky_radiance[0] ? ", sky radiance " : "", alias.sky_radiance);
    snprintf(p->atmosphere_name, sizeof p->atmosphere_name, "%s", scene->atmosphere.name);
    snprintf(p->atmosphere_hash, sizeof p->atmosphere_hash, "%s", rep->atmosphere_hash);
    p->domain = rep->domain;
    p->viewer_max_km = scene->viewer_altitude_km[1];
    snprintf(p->error, sizeof p->error, "that of the models above");
    p->emit = sf_emit_selection_alias;
    p->model = &alias;
  }
  /* A spectral4 scene also ships its 4 wavelengths, weights and matrices
   * (SPEC §7.3), emitted from the weights file as `skyfit codegen` does. */
  sf_weights spectral4_weights;
  sf_fitted_model *spectral4_model = NULL;
  memset(&spectral4_weights, 0, sizeof spectral4_weights);
  if (rep->spectral4.present && rep->spectral4.weights_path[0]) {
    int st = sf_weights_load_file(rep->spectral4.weights_path, "spectral4", &spectral4_weights, err);
    if (st == SF_OK) st = sf_fitted_part(&spectral4_weights, &spectral4_model, &parts[n], err);
    if (st != SF_OK) {
      sf_fitted_free(spectral4_model);   /* sf_fitted_part leaves *model to free on failure too */
      sf_weights_free(&spectral4_weights);
      return st;
    }
    ++n;
  }
  if (n == 0) return SF_OK;
  int status = sf_build_header_paths(scene, o, res->header_c, res->header_glsl, sizeof res->header_c, err);
  if (status == SF_OK) status = sf_codegen_prepare_files(parts, n, res->header_c, res->header_glsl, o->prefix, headers, err);
  sf_fitted_free(spectral4_model);
  sf_weights_free(&spectral4_weights);
  if (status != SF_OK) {
    res->header_c[0] = res->header_glsl[0] = '\0';
    return status;
  }
  for (int q = 0; q < SF_CANDIDATE_N_QUANTITIES; ++q) {
    sf_report_selection *s = &rep->selection[q];
    if (!s->asked || s->model < 0 || !rep->models[s->model].candidate->emit) continue;
    /* the report's paths are all from its folder (its views' too) */
    sf_path_from_folder(o->out_dir, res->header_c, s->emitted_c, sizeof s->emitted_c);
    sf_path_from_folder(o->out_dir, res->header_glsl, s->emitted_glsl, sizeof s->emitted_glsl);
  }
  return SF_OK;
}

/* The user's notes, also kept for the report. */
typedef struct note_log {
  char text[4096];
  sf_candidate_note_fn forward;
  void *forward_ctx;
} note_log;

static void log_note(void *ctx, const char *message) {
  note_log *l = ctx;
  size_t len = strlen(l->text);
  snprintf(l->text + len, sizeof l->text - len, "%s\n", message);
  if (l->forward) l->forward(l->forward_ctx, message);
}

void sf_build_table_options(const sf_scene *scene, const sf_scene_domain *domain,
                            const sf_table_set_options *base, const char *cache_dir,
                            sf_table_set_options *out) {
  *out = *base;
  out->cache_dir = cache_dir;
  out->has_domain = 1;
  out->domain.h_min_km = domain->h_min_km;
  out->domain.h_max_km = domain->h_max_km;
  out->domain.mu_min = domain->mu_min;
  out->domain.mu_s_min = domain->mu_s_min;
  out->domain.mu_s_max = domain->mu_s_max;
  out->domain.sky_only = scene->view == SF_VIEW_ABOVE_HORIZON;
  out->transmittance_only = !(scene->quantities & SF_QUANTITY_SKY_RADIANCE);
}

/* The reference's own error where it can be computed directly: the sky
 * tables' single scattering against direct integration on domain samples
 * (data/sky_table_check.h; 5000 take 0.7-0.9 s on 2 cores, the direct
 * integration's; --quick checks 1000). */
#define REFERENCE_CHECK_POINTS 5000
#define REFERENCE_CHECK_POINTS_QUICK 1000
static int reference_check(sf_report *rep, const sf_sky_tables *sky, const sf_build_options *o, sf_error *err) {
  sf_domain_samples s;
  size_t n = o->quick ? REFERENCE_CHECK_POINTS_QUICK : REFERENCE_CHECK_POINTS;
  if (sf_domain_samples_make(&rep->domain, SF_CANDIDATE_SKY_RADIANCE, n, o->report.seed + 2, &s, err) != SF_OK)
    return err->status;
  int status = sf_sky_table_check_points(sky, s.inputs, s.n, &o->report.run, &rep->reference_check, err);
  sf_domain_samples_free(&s);
  return status;
}

/* The smallest budget metric of quantity q's networks (and their
 * restarts), over its budget: how far a restart would have to bring it
 * down. INFINITY where no network was measured. */
static double network_miss(const sf_report *rep, int q) {
  double best = INFINITY;
  for (int i = 0; i < rep->n_models; ++i) {
    const sf_report_model *m = &rep->models[i];
    if ((int)m->candidate->quantity != q || !m->has_errors || !isfinite(m->budget_metric)) continue;
    if (!sf_candidate_network_name(m->candidate->name, strlen(m->candidate->name))) continue;
    if (m->budget_metric < best) best = m->budget_metric;
  }
  return best / rep->selection[q].budget;
}

/* OUT/cache under o->cache_limit_bytes, this run's entries kept: those it
 * wrote or hit since run_start, less a second (file times come from a
 * coarser clock than clock_gettime's). A failure is reported, not fatal. */
static void prune_cache(const char *cache, const sf_build_options *o, struct timespec run_start,
                        sf_build_result *res) {
  struct timespec used_since = run_start;
  used_since.tv_sec -= 1;
  sf_error problem = {0};
  if (sf_cache_prune(cache, o->cache_limit_bytes, used_since, &res->cache, &problem) != SF_OK)
    snprintf(res->cache_problem, sizeof res->cache_problem, "%s", problem.message);
}

/* Weights files an earlier run left in OUT/weights for models this run
 * did not fit (fit/build_stale_weights.h). A failure is reported, not fatal. */
static void remove_stale_weights(const char *work, const sf_candidate_list *list, const sf_report_spectral4 *s4,
                                 sf_build_result *res) {
  const char **written = calloc((size_t)list->count + 1, sizeof *written);
  if (!written) {
    snprintf(res->weights_problem, sizeof res->weights_problem, "out of memory listing the weights files");
    return;
  }
  int n = 0;
  for (int i = 0; i < list->count; ++i)
    if (list->items[i].weights_path[0]) written[n++] = list->items[i].weights_path;
  if (s4->present && s4->weights_path[0]) written[n++] = s4->weights_path;
  sf_error problem = {0};
  if (sf_build_remove_stale_weights(work, written, n, &res->weights_removed, &problem) != SF_OK)
    snprintf(res->weights_problem, sizeof res->weights_problem, "%s", problem.message);
  free(written);
}

/* The weights files' paths as they will be once published: the report
 * names those, not the staging folder's. */
static void weights_paths_final(const sf_build_staging *stage, sf_candidate_list *list, sf_report_spectral4 *s4) {
  char path[4096];
  for (int i = 0; i < list->count; ++i) {
    sf_build_staging_final_path(stage, list->items[i].weights_path, path, sizeof path);
    snprintf(list->items[i].weights_path, sizeof list->items[i].weights_path, "%s", path);
  }
  if (s4->present) {
    sf_build_staging_final_path(stage, s4->weights_path, path, sizeof path);
    snprintf(s4->weights_path, sizeof s4->weights_path, "%s", path);
  }
}

int sf_build_run(const sf_scene *scene, const sf_build_options *o, sf_build_result *res, sf_error *err) {
  memset(res, 0, sizeof *res);
  double t_start = sf_wall_seconds(), c_start = sf_cpu_seconds();
  struct timespec run_start;
  clock_gettime(CLOCK_REALTIME, &run_start);
  sf_scene_domain domain;
  if (sf_scene_get_domain(scene, &domain, err) != SF_OK) return err->status;
  char cache[SF_REPORT_PATH_LEN + 16], work[SF_REPORT_PATH_LEN + 16];
  snprintf(cache, sizeof cache, "%s/cache", o->out_dir);
  snprintf(work, sizeof work, "%s/weights", o->out_dir);

  sf_table_set_options topt;
  sf_build_table_options(scene, &domain, &o->tables, cache, &topt);
  topt.problem = o->note;   /* a damaged cached table: said, not reported */
  topt.problem_ctx = o->note_ctx;
  /* Bad input (an impossible resolution, tables larger than memory allows)
   * is refused before anything is created: nothing written on bad input. */
  if (sf_table_set_check(&scene->atmosphere, &topt, err) != SF_OK) return err->status;
  if (sf_build_spectral4_check(scene, err) != SF_OK) return err->status;
  struct stat out_stat;
  int out_existed = stat(o->out_dir, &out_stat) == 0;
  if (sf_make_folders(o->out_dir, "--out", err) != SF_OK) return err->status;
  /* The outputs' paths, checked before the work and before anything else
   * is created: a scene naming a missing folder, or a folder where the
   * report goes, fails now, not after the fits. */
  char c_path[SF_REPORT_PATH_LEN], glsl_path[SF_REPORT_PATH_LEN];
  if ((o->emit && (sf_build_header_paths(scene, o, c_path, glsl_path, sizeof c_path, err) != SF_OK ||
                   sf_codegen_check_files(c_path, glsl_path, err) != SF_OK)) ||
      sf_build_staging_check_out(o->out_dir, err) != SF_OK) {
    if (!out_existed) rmdir(o->out_dir);
    return err->status;
  }
  /* OUT/weights is made when the staged run is published: a run that
   * fails (a full disk while the tables are written) leaves none behind. */
  if (sf_make_folders(cache, "--out", err) != SF_OK) return err->status;
  sf_table_set set;
  if (sf_table_set_make(&set, &scene->atmosphere, &topt, err) != SF_OK) return err->status;
  for (int t = 0; t < set.n_tables; ++t) res->tables_from_cache += set.from_cache[t];
  res->tables_total = set.n_tables;
  double t_tables = sf_wall_seconds(), c_tables = sf_cpu_seconds();
  res->seconds_tables = t_tables - t_start;
  res->cpu_seconds_tables = c_tables - c_start;

  sf_sky_tables sky;
  sf_sky_tables_of_set(&sky, &scene->atmosphere, &set);
  note_log *notes = calloc(1, sizeof *notes);
  if (!notes) {
    sf_table_set_free(&set);
    return sf_fail(err, SF_ERR_INTERNAL, "out of memory");
  }
  notes->forward = o->note;
  notes->forward_ctx = o->note_ctx;
  char orders_short[640];
  if (sf_table_set_orders_short(&set, &topt, orders_short, sizeof orders_short)) log_note(notes, orders_short);
  /* the atmosphere's, so a rerun from the cache says it too */
  if (topt.orders >= 2 && sf_phase_peaks_note(&scene->atmosphere, orders_short, sizeof orders_short))
    log_note(notes, orders_short);
  /* Weights, views and report go to a staging folder, published when the
   * run has succeeded (fit/build_staging.h); the cache is written as it goes. */
  sf_build_staging stage;
  char staged_work[sizeof stage.dir + 16];
  if (sf_build_staging_open(&stage, o->out_dir, err) != SF_OK) {
    free(notes);
    sf_table_set_free(&set);
    return err->status;
  }
  snprintf(staged_work, sizeof staged_work, "%s/weights", stage.dir);
  if (sf_make_folders(staged_work, "--out", err) != SF_OK) {
    sf_build_staging_discard(&stage);
    free(notes);
    sf_table_set_free(&set);
    return err->status;
  }
  sf_codegen_files headers;
  memset(&headers, 0, sizeof headers);
  sf_candidate_inputs in = {.scene = scene, .domain = domain, .atm = &scene->atmosphere, .tables = &set,
                            .sky = &sky, .work_dir = staged_work, .cache_dir = cache,
                            .orders = topt.orders, .seed = o->report.seed, .quick = o->quick,
                            .mlp_transmittance_epochs = o->mlp_transmittance_epochs,
                            .mlp_scattering_epochs = o->mlp_scattering_epochs,
                            .mlp_scattering_samples = o->mlp_scattering_samples,
                            .mlp_scattering_normalise = o->mlp_scattering_normalise,
                            .mlp_scattering_normalise_cap = o->mlp_scattering_normalise_cap,
                            .mlp_scattering_loss_floor = o->mlp_scattering_loss_floor, .run = o->report.run,
                            .exclude = o->exclude,
                            .note = log_note, .note_ctx = notes};
  sf_candidate_list list;
  sf_candidate_list_init(&list);
  int status = sf_candidates_make_all(&in, &list, log_note, notes, err);

  /* A spectral4 scene: the 4-wavelength colour model (SPEC §7.3). */
  sf_report_spectral4 spectral4;
  memset(&spectral4, 0, sizeof spectral4);
  if (status == SF_OK && scene->color == SF_COLOR_SPECTRAL4 && (scene->quantities & SF_QUANTITY_SKY_RADIANCE)) {
    sf_build_spectral4_options so = {.cache_dir = cache, .work_dir = staged_work, .quick = o->quick, .run = o->report.run,
                                     .note = log_note, .note_ctx = notes};
    status = sf_build_spectral4(scene, &so, &spectral4, err);
  }
  double t_fit = sf_wall_seconds(), c_fit = sf_cpu_seconds();
  res->seconds_fit = t_fit - t_tables;
  res->cpu_seconds_fit = c_fit - c_tables;

  sf_report rep;
  memset(&rep, 0, sizeof rep);
  sf_report_options ropt = o->report;
  ropt.cost_cache_dir = cache;
  if (status == SF_OK) status = sf_report_evaluate(&rep, scene, &list, &ropt, stage.dir, err);   /* and selected */
  /* A network that missed the budget may meet it from another start: the
   * seed's next restart is trained, measured beside it, and the selection
   * made again, up to the build's number of networks per quantity. By
   * default not where the networks miss it by more than the seeds' spread
   * (SF_BUILD_RESTART_MAX_MISS). */
  double seconds_restarts = 0.0, cpu_seconds_restarts = 0.0;
  int max_networks = o->mlp_restarts > 0 ? o->mlp_restarts : o->quick ? 1 : SF_BUILD_MLP_RESTARTS;
  for (int restart = 1; status == SF_OK && restart < max_networks; ++restart) {
    int missed[SF_CANDIDATE_N_QUANTITIES], any = 0;
    for (int q = 0; q < SF_CANDIDATE_N_QUANTITIES; ++q) {
      missed[q] = rep.selection[q].asked && !rep.selection[q].meets_budget;
      double miss = missed[q] && o->mlp_restarts <= 0 ? network_miss(&rep, q) : 0.0;
      if (miss > SF_BUILD_RESTART_MAX_MISS) {
        missed[q] = 0;
        if (restart == 1 && isfinite(miss)) {
          char text[400];
          snprintf(text, sizeof text,
                   "%s: the best network misses the budget %.3g by %.1fx; no restart trained: over seeds 1-12 "
                   "of the default build the networks' errors spread 1.5-1.6x (--mlp-restarts N trains them "
                   "anyway)",
                   sf_candidate_quantity_name((sf_candidate_quantity)q), rep.selection[q].budget, miss);
          log_note(notes, text);
        }
      }
      any |= missed[q];
    }
    if (!any) break;
    double t0 = sf_wall_seconds(), c0 = sf_cpu_seconds();
    sf_report_free(&rep);   /* it points into the list, which the restarts grow */
    in.restart = restart;
    int added = 0;
    for (int q = 0; q < SF_CANDIDATE_N_QUANTITIES && status == SF_OK; ++q) {
      if (!missed[q]) continue;
      int n = 0;
      status = sf_candidates_make_restart(&in, (sf_candidate_quantity)q, &list, &n, log_note, notes, err);
      if (status == SF_OK && n > 0) {
        char text[300];
        snprintf(text, sizeof text, "%s: no model met the budget; trained restart %d of the seed's network (%s)",
                 sf_candidate_quantity_name((sf_candidate_quantity)q), restart + 1, list.items[list.count - 1].name);
        log_note(notes, text);
      }
      added += n;
    }
    seconds_restarts += sf_wall_seconds() - t0;
    cpu_seconds_restarts += sf_cpu_seconds() - c0;
    if (status == SF_OK) status = sf_report_evaluate(&rep, scene, &list, &ropt, stage.dir, err);   /* and selected */
    if (!added) break;
  }
  res->seconds_fit += seconds_restarts;
  res->cpu_seconds_fit += cpu_seconds_restarts;
  if (status == SF_OK) status = sf_build_record_errors(&rep, err);
  rep.spectral4 = spectral4;
  if (status == SF_OK && (scene->quantities & SF_QUANTITY_SKY_RADIANCE) && sky.multiple)
    status = reference_check(&rep, &sky, o, err);
  snprintf(rep.notes, sizeof rep.notes, "%s", notes->text);
  free(notes);
  if (status == SF_OK && o->emit) status = emit_selection(&rep, scene, o, res, &headers, err);
  res->seconds_report = sf_wall_seconds() - t_fit - seconds_restarts;
  res->cpu_seconds_report = sf_cpu_seconds() - c_fit - cpu_seconds_restarts;
  res->seconds_total = sf_wall_seconds() - t_start;
  rep.seconds_total = res->seconds_total;
  if (status == SF_OK) status = sf_report_write_all(&rep, err);   /* weights named from its folder */
  weights_paths_final(&stage, &list, &rep.spectral4);
  /* Everything written: the headers and the staged outputs into place
   * together; otherwise none of them, the previous outputs untouched. */
  if (status == SF_OK) status = sf_build_staging_check(&stage, err);
  sf_signal_defer burst;   /* a Ctrl-C lands after the renames, not between them */
  sf_signal_defer_begin(&burst);
  if (status == SF_OK) status = sf_codegen_commit_files(&headers, err);
  if (status == SF_OK) status = sf_build_staging_publish(&stage, err);
  sf_signal_defer_end(&burst);
  sf_codegen_abort_files(&headers);
  sf_build_staging_discard(&stage);
  if (status == SF_OK) {
    snprintf(res->report_html, sizeof res->report_html, "%s/report.html", o->out_dir);
    for (int q = 0; q < SF_CANDIDATE_N_QUANTITIES; ++q) {
      const sf_report_selection *s = &rep.selection[q];
      res->asked[q] = s->asked;
      res->meets_budget[q] = s->meets_budget;
      snprintf(res->chosen[q], sizeof res->chosen[q], "%s", s->model >= 0 ? rep.models[s->model].candidate->name : "");
    }
    prune_cache(cache, o, run_start, res);
    remove_stale_weights(work, &list, &rep.spectral4, res);
    sf_error problem = {0};
    if (sf_report_remove_stale_pictures(&rep, o->out_dir, &res->views_removed, &problem) != SF_OK)
      snprintf(res->views_problem, sizeof res->views_problem, "%s", problem.message);
  }
  sf_report_free(&rep);
  sf_candidate_list_free(&list);
  sf_table_set_free(&set);
  return status;
}
