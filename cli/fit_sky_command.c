#include "cli/fit_sky_command.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cjson/cJSON.h>

#include "cli/atmosphere_warnings.h"
#include "cli/csv_points.h"
#include "cli/interrupt_cleanup.h"
#include "cli/option_value.h"
#include "cli/output_file_check.h"
#include "cli/progress_bar.h"
#include "cli/size_pair_option.h"
#include "cli/table_options.h"
#include "data/sky_lookup.h"
#include "data/table_set.h"
#include "fit/fit_sky_config.h"
#include "fit/fit_sky_elevation.h"
#include "fit/fit_weights_doc.h"
#include "fit/sky_radiance_samples.h"
#include "models/atmosphere_file.h"
#include "models/hosek_dataset.h"
#include "models/preetham.h"
#include "models/scene_file.h"
#include "models/weights_file.h"
#include "util/constants.h"
#include "util/json_exact.h"

static const char *const perez_letters[] = {"A", "B", "C", "D", "E"};
static const char *const hosek_letters[] = {"A", "B", "C", "D", "E", "F", "G", "H", "I"};

static void usage(sf_sky_form form, FILE *out) {
  const char *m = sf_sky_form_model_name(form);
  fprintf(out,
          "usage: skyfit fit %s [--scene S.json] [--tables DIR] [table options] --out W.json\n"
          "       skyfit fit %s --samples SKY.csv [--scale S] [--unbounded]\n"
          "       skyfit fit %s --check W.json\n"
          "\n",
          m, m, m);
  if (form == SF_SKY_FORM_HOSEK)
    fprintf(out,
            "Fits the Hosek-Wilkie 2012 sky F(theta,gamma) (9 coefficients A..I, radiance scale R)\n");
  else
    fprintf(out, "Fits the Perez/Preetham sky K F(theta,gamma) (5 coefficients A..E, scale K)\n");
  fprintf(out,
          "to the reference ground-level sky radiance (single + multiple scattering, phase functions)\n"
          "per sun elevation and channel, then its dependence on sun elevation as Hosek does (quintic\n"
          "Bezier in (elevation/(pi/2))^(1/3), 6 control points per coefficient), over the scene's sun\n"
          "range above the horizon; writes the weights file (SPEC §8) with the fit metrics and the\n"
          "published models' error on the same samples. Ground viewer, sun up only (SPEC §5): a\n"
          "--scene must include a ground viewer; its sun range is the one fitted.\n"
          "\n"
          "With --samples, fits one sky to a CSV with columns theta,gamma,radiance (radians) and\n"
          "prints the coefficients (paper order) and the scale as JSON on stdout. %s\n"
          "\n"
          "options:\n"
          "  --out W.json            weights file to write (atomically)\n"
          "  --tables DIR            reference table folder (cache of 'skyfit sample'); default: in memory\n"
          "  --elevations N          sun elevations fitted (>= 6, default 19)\n"
          "  --grid NTxNP            view directions per elevation, zenith x azimuth (default 16x24)\n"
          "  --samples SKY.csv       fit one sky to these samples instead\n"
          "  --scale S               --samples: hold the radiance scale at S%s\n"
          "  --unbounded             --samples: only the scale is bounded (>= 0); default also %s\n"
          "  --check W.json          validate a weights file of this model; exit 2 if invalid\n",
          form == SF_SKY_FORM_HOSEK ? "The scale is degenerate with C, D, F, G, I, so it is held "
                                      "fixed (default 1)."
                                    : "K is free unless --scale fixes it.",
          form == SF_SKY_FORM_HOSEK ? " (default 1)" : "",
          form == SF_SKY_FORM_HOSEK ? "H in [0, 0.999], B <= 0" : "B <= 0");
  sf_table_cli_help(out);
  fprintf(out, "  --help                  this text\n");
}

static int parse_double(const char *text, double *out) {
  char *end;
  errno = 0;
  double v = strtod(text, &end);
  if (end == text || *end != '\0' || errno == ERANGE || !isfinite(v)) return -1;
  *out = v;
  return 0;
}

/* ---- --samples ----------------------------------------------------------- */

static int fit_samples(sf_sky_form form, const char *command, const char *path, int scale_given,
                       double scale_value, int unbounded) {
  FILE *in = fopen(path, "r");
  if (!in) {
    fprintf(stderr, "%s: --samples: cannot open %s: %s\n", command, path, strerror(errno));
    return 2;
  }
  static const char *const columns[] = {"theta", "gamma", "radiance", NULL};
  sf_csv_points pts;
  sf_error err = {0};
  int rc = sf_csv_points_read(in, path, columns, columns, &pts, &err);
  fclose(in);
  if (rc != SF_OK) {
    fprintf(stderr, "%s: %s\n", command, err.message);
    return err.status;
  }
  int n = (int)pts.n_rows;
  int ct = sf_csv_points_column(&pts, "theta"), cg = sf_csv_points_column(&pts, "gamma"),
      cr = sf_csv_points_column(&pts, "radiance");
  sf_sky_samples s;
  if (n < 12) {
    fprintf(stderr, "%s: %s: need at least 12 samples, got %d\n", command, path, n);
    sf_csv_points_free(&pts);
    return 2;
  }
  if (sf_sky_samples_alloc(&s, n, 1, &err) != SF_OK) {
    fprintf(stderr, "%s: %s\n", command, err.message);
    sf_csv_points_free(&pts);
    return 1;
  }
  double ss = 0;
  for (int i = 0; i < n; ++i) {
    double theta = pts.values[i * pts.n_columns + ct], gamma = pts.values[i * pts.n_columns + cg];
    double L = pts.values[i * pts.n_columns + cr];
    /* a negative radiance had been fitted silently */
    if (!(theta >= 0 && theta < 0.5 * SF_PI) || !(gamma >= 0 && gamma <= SF_PI) || !(L >= 0)) {
      fprintf(stderr,
              "%s: %s: row %ld: need 0 <= theta < pi/2, 0 <= gamma <= pi (radians) and a radiance >= 0, "
              "got %g, %g, %g\n",
              command, path, sf_csv_points_line(&pts, i), theta, gamma, L);
      sf_sky_samples_free(&s);
      sf_csv_points_free(&pts);
      return 2;
    }
    sf_sky_sample_set_angles(&s, i, theta, cos(gamma));
    s.gamma[i] = gamma;
    s.radiance[i] = L;
    ss += L * L;
  }
  sf_csv_points_free(&pts);
  if (!(ss > 0)) {
    fprintf(stderr, "%s: %s: every radiance is 0\n", command, path);
    sf_sky_samples_free(&s);
    return 2;
  }
  /* A radiance of 1e300 had ended as a "converged" fit of rmse null. */
  if (!isfinite(ss)) {
    fprintf(stderr, "%s: %s: radiance: the squares overflow double; scale the radiances down\n", command, path);
    sf_sky_samples_free(&s);
    return 2;
  }
  int nc = sf_sky_form_n_coeffs(form);
  sf_sky_fit_data d = {form, n, s.cos_theta, s.gamma, s.cos_gamma, s.radiance, 1, 1.0 / sqrt(ss / n)};
  sf_sky_bounds bounds = unbounded ? SF_SKY_BOUNDS_SCALE_ONLY : SF_SKY_BOUNDS_PHYSICAL;
  int fix_scale = form == SF_SKY_FORM_HOSEK || scale_given;
  double scale = scale_given ? scale_value : 1.0;
  /* Starts: the published sets at turbidities 2, 4, 7 (Hosek: green channel,
   * albedo 0, sun at 10 and 45 degrees), their linear part fitted to the data. */
  enum { MAX_STARTS = 6 };
  double starts[MAX_STARTS][SF_HOSEK_N_COEFFS + 1];
  char names[MAX_STARTS][48];
  int n_starts = 0;
  sf_hosek_dataset *published = NULL;
  if (form == SF_SKY_FORM_HOSEK) {
    published = malloc(sizeof *published);
    if (!published || sf_hosek_dataset_load_default(published, &err) != SF_OK) {
      fprintf(stderr, "%s: %s\n", command, published ? err.message : "out of memory");
      free(published);
      sf_sky_samples_free(&s);
      return published ? err.status : 1;
    }
  }
  const double turbidities[3] = {2, 4, 7}, elevations_deg[2] = {10, 45};
  for (int t = 0; t < 3; ++t)
    for (int e = 0; e < (form == SF_SKY_FORM_HOSEK ? 2 : 1); ++e) {
      double *c = starts[n_starts], R;
      if (form == SF_SKY_FORM_HOSEK) {
        sf_hosek_dataset_state(published, 1, turbidities[t], 0.0, elevations_deg[e] * SF_PI / 180,
                               c, &R, &err);
        snprintf(names[n_starts], 48, "published Hosek G T=%.0f elevation %.0f deg", turbidities[t],
                 elevations_deg[e]);
      } else {
        sf_preetham_coefficients(SF_PREETHAM_Y, turbidities[t], c);
        snprintf(names[n_starts], 48, "published Preetham Y T=%g", turbidities[t]);
      }
      double md = 0, mm = 0;
      for (int i = 0; i < n; ++i) {
        double f = sf_sky_form_f(form, c, s.cos_theta[i], s.gamma[i], s.cos_gamma[i], NULL);
        md += f * s.radiance[i];
        mm += f * f;
      }
      double a = mm > 0 ? md / mm : 1.0;
      if (form == SF_SKY_FORM_HOSEK || scale_given) {
        double factor = a / scale;
        const int linear[5] = {SF_HOSEK_C, SF_HOSEK_D, SF_HOSEK_F, SF_HOSEK_G, SF_HOSEK_I};
        if (form == SF_SKY_FORM_HOSEK)
          for (int q = 0; q < 5; ++q) c[linear[q]] *= factor;
        c[nc] = scale;
      } else {
        c[nc] = a;
      }
      ++n_starts;
    }
  free(published);
  sf_lsq_options lsq;
  sf_sky_fit_options_default(&lsq);
  double coeffs[SF_HOSEK_N_COEFFS], final_costs[MAX_STARTS];
  int winner;
  sf_lsq_summary sum;
  rc = sf_fit_sky_multistart(&d, bounds, fix_scale, &lsq, n_starts, (const double(*)[SF_HOSEK_N_COEFFS + 1])starts, coeffs, &scale,
                             &winner, &sum, final_costs, &err);
  if (rc != SF_OK) {
    fprintf(stderr, "%s: %s\n", command, err.message);
    sf_sky_samples_free(&s);
    return 1;
  }
  double sse = 0, sse_rel = 0;
  int n_rel = 0;
  for (int i = 0; i < n; ++i) {
    double m = scale * sf_sky_form_f(form, coeffs, s.cos_theta[i], s.gamma[i], s.cos_gamma[i], NULL);
    double dlt = m - s.radiance[i];
    sse += dlt * dlt;
    if (s.radiance[i] != 0) {
      sse_rel += dlt * dlt / (s.radiance[i] * s.radiance[i]);
      ++n_rel;
    }
  }
  sf_sky_samples_free(&s);
  int finite = isfinite(sse) && isfinite(scale);
  for (int i = 0; i < nc; ++i) finite = finite && isfinite(coeffs[i]);
  if (!finite) {
    fprintf(stderr, "%s: %s: the fit gave non-finite values\n", command, path);
    return 1;
  }
  cJSON *root = cJSON_CreateObject();
  cJSON_AddStringToObject(root, "model", sf_sky_form_model_name(form));
  cJSON *co = cJSON_AddObjectToObject(root, "coefficients");
  for (int i = 0; i < nc; ++i)
    cJSON_AddNumberToObject(co, form == SF_SKY_FORM_HOSEK ? hosek_letters[i] : perez_letters[i],
                            coeffs[i]);
  cJSON_AddNumberToObject(root, "scale", scale);
  cJSON_AddBoolToObject(root, "scale_fixed", fix_scale);
  cJSON_AddNumberToObject(root, "samples", n);
  cJSON_AddNumberToObject(root, "rmse", sqrt(sse / n));
  cJSON_AddNumberToObject(root, "rel_rmse", n_rel ? sqrt(sse_rel / n_rel) : 0.0);
  cJSON_AddNumberToObject(root, "final_cost", sum.final_cost);
  cJSON_AddNumberToObject(root, "iterations", sum.iterations);
  cJSON_AddStringToObject(root, "termination", sf_lsq_termination_name(sum.termination));
  cJSON_AddStringToObject(root, "bounds", unbounded ? "scale only" : "physical");
  cJSON_AddStringToObject(root, "winning_start", names[winner]);
  cJSON *starts_json = cJSON_AddArrayToObject(root, "starts");
  for (int q = 0; q < n_starts; ++q) {
    cJSON *e = cJSON_CreateObject();
    cJSON_AddStringToObject(e, "start", names[q]);
    if (isfinite(final_costs[q])) cJSON_AddNumberToObject(e, "final_cost", final_costs[q]);
    else cJSON_AddNullToObject(e, "final_cost");
    cJSON_AddItemToArray(starts_json, e);
  }
  char *text = sf_json_print_exact(root, 1);
  cJSON_Delete(root);
  if (!text) return 1;
  printf("%s\n", text);
  free(text);
  return sf_cli_stdout_written(command);   /* the result is this output */
}

/* ---- --check ------------------------------------------------------------- */

static int check_weights(sf_sky_form form, const char *command, const char *path) {
  sf_elevation_sky_model *m = malloc(sizeof *m);
  sf_error err = {0};
  if (!m) return 1;
  int rc = sf_elevation_sky_load(path, form, m, NULL, &err);
  if (rc == SF_OK) {
    double x[SF_MAX_CHANNELS];
    sf_elevation_sky_radiance(m, 0.5 * (m->elevation_min_rad + m->elevation_max_rad), 0.0, 0.5, x);
    for (int k = 0; k < m->n_channels && rc == SF_OK; ++k)
      if (!isfinite(x[k]))
        rc = sf_fail(&err, SF_ERR_INPUT, "%s: params: the model evaluates to a non-finite radiance",
                     path);
  }
  if (rc == SF_OK)
    printf("%s: valid %s weights, %d channels, sun %.4g..%.4g deg\n", path,
           sf_sky_form_model_name(form), m->n_channels, m->elevation_min_rad * 180 / SF_PI,
           m->elevation_max_rad * 180 / SF_PI);
  else fprintf(stderr, "%s: %s\n", command, err.message);
  free(m);
  return rc;
}

/* ---- table fit ----------------------------------------------------------- */

static int fit_tables(sf_sky_form form, const char *command, sf_table_cli *o, const char *scene_path,
                      const char *tables_dir, const char *out_path, int n_elevations, int n_theta,
                      int n_phi) {
  sf_error err = {0};
  sf_scene *scene = malloc(sizeof *scene);
  sf_atmosphere *atm = malloc(sizeof *atm);
  sf_sky_elevation_report *rep = malloc(sizeof *rep);
  sf_elevation_sky_model *model = malloc(sizeof *model);
  sf_hosek_dataset *published = malloc(sizeof *published);
  sf_table_set set;
  memset(&set, 0, sizeof set);
  int status = (scene && atm && rep && model && published) ? SF_OK : SF_ERR_INTERNAL;
  if (status != SF_OK) sf_fail(&err, SF_ERR_INTERNAL, "out of memory");
  if (status == SF_OK) {
    if (scene_path) {
      if (o->atmosphere_path)
        status = sf_fail(&err, SF_ERR_INPUT, "--atmosphere and --scene: give one (the scene names its atmosphere)");
      else status = sf_scene_load_file(scene_path, scene, &err);
    } else {
      sf_scene_default(scene);
      if (o->atmosphere_path) status = sf_atmosphere_load_file(o->atmosphere_path, &scene->atmosphere, &err);
    }
    if (status == SF_OK)
      sf_cli_warn_atmosphere_units(command, o->atmosphere_path ? o->atmosphere_path : scene->atmosphere_path,
                                   &scene->atmosphere);
  }
  sf_scene_domain domain;
  if (status == SF_OK) status = sf_scene_get_domain(scene, &domain, &err);
  if (status == SF_OK && (domain.h_min_km > 0.0 || scene->viewer_altitude_km[0] > 0.0))
    status = sf_fail(&err, SF_ERR_INPUT,
                     "%s: viewer_altitude_km: starts at %g km; Preetham and Hosek hold only for a "
                     "viewer on the ground (SPEC §5)",
                     scene_path ? scene_path : "scene", scene->viewer_altitude_km[0]);
  if (status == SF_OK && scene->sun_elevation_deg[1] <= 0.0)
    status = sf_fail(&err, SF_ERR_INPUT,
                     "%s: sun_elevation_deg: the sun never rises; Preetham and Hosek hold only "
                     "for a sun above the horizon (SPEC §5)",
                     scene_path ? scene_path : "scene");
  /* A single elevation (or none above the horizon) has no curve to fit:
   * the fit had said so only after the tables, naming neither file nor key. */
  if (status == SF_OK && !(fmax(scene->sun_elevation_deg[0], 0.0) < scene->sun_elevation_deg[1]))
    status = sf_fail(&err, SF_ERR_INPUT,
                     "%s: sun_elevation_deg: [%g, %g] is a single elevation above the horizon; the fit across "
                     "elevations needs a range (e.g. [0, 90])",
                     scene_path ? scene_path : "scene", scene->sun_elevation_deg[0], scene->sun_elevation_deg[1]);
  if (status == SF_OK) {
    const char *inputs[3];
    sf_cli_scene_files(scene_path, o->atmosphere_path, scene, inputs);
    status = sf_cli_output_problem("--out", out_path, inputs, 3, &err);
  }
  /* a signal leaves no temporary of the weights or a table
   * (cli/interrupt_cleanup.h) */
  sf_cli_outputs outputs = {0};
  sf_cli_outputs_add_file(&outputs, out_path);
  sf_cli_outputs_add_folder(&outputs, tables_dir);
  if (status == SF_OK) sf_cli_supervise_outputs(&outputs);
  if (status == SF_OK) status = sf_hosek_dataset_load_default(published, &err);
  if (status == SF_OK) {
    *atm = scene->atmosphere;
    o->set.cache_dir = tables_dir;
    status = sf_table_set_check(atm, &o->set, &err);
  }
  sf_progress_bar bar;
  sf_progress_bar_init(&bar, stderr, !o->quiet);
  bar.note_prefix = "skyfit fit";
  if (status == SF_OK) {
    o->set.run.progress = sf_progress_bar_update;
    o->set.run.progress_ctx = &bar;
    if (!o->quiet) {
      o->set.note = sf_progress_bar_note;
      o->set.note_ctx = &bar;
    }
    status = sf_table_set_make(&set, atm, &o->set, &err);
  }
  if (status == SF_OK) {
    sf_sky_tables sky;
    sf_sky_tables_of_set(&sky, atm, &set);
    sf_sky_elevation_options opt;
    sf_sky_elevation_options_default(&opt, form);
    opt.elevation_min_rad = fmax(scene->sun_elevation_deg[0], 0.0) * SF_PI / 180.0;
    opt.elevation_max_rad = scene->sun_elevation_deg[1] * SF_PI / 180.0;
    if (n_elevations) opt.n_elevations = n_elevations;
    if (n_theta) opt.n_theta = n_theta, opt.n_phi = n_phi;
    opt.progress = sf_progress_bar_update;
    opt.progress_ctx = &bar;
    status = sf_fit_sky_elevation(&sky, &opt, published, model, rep, &err);
    sf_progress_bar_finish(&bar);
    sf_scene_domain wd = {0.0, 0.0, 0.0, 1.0, sin(model->elevation_min_rad), sin(model->elevation_max_rad)};
    if (status == SF_OK)
      status = sf_sky_form_weights_write(atm, &wd, &opt, sf_parameterization_name(set.params.kind), model, rep,
                                         out_path, &err);
  } else {
    sf_progress_bar_finish(&bar);
  }
  if (status == SF_OK && !o->quiet) {
    fprintf(stderr, "%s: %d sun elevations %.3g..%.3g deg, %d samples per channel\n", command,
            rep->n_elevations, rep->elevation_rad[0] * 180 / SF_PI,
            rep->elevation_rad[rep->n_elevations - 1] * 180 / SF_PI, rep->n_samples);
    fprintf(stderr, "%s: rmse %.4g at %d sun elevations, %.4g at the %d held out between the fitted ones (relative %.4g, "
            "max abs %.4g at sun %.3g deg, theta %.3g, gamma %.3g deg); per-elevation fits %.4g\n",
            command, rep->rmse, rep->n_metric_elevations, rep->held_out_rmse, rep->n_metric_elevations - rep->n_elevations,
            rep->rel_rmse, rep->max_abs, rep->worst_elevation_rad * 180 / SF_PI,
            rep->worst_theta * 180 / SF_PI, rep->worst_gamma * 180 / SF_PI, rep->per_elevation_rmse);
    fprintf(stderr, "%s: published Preetham rmse %.4g (T = %.3g), published Hosek rmse %.4g (T = %.3g), best per-channel scale\n",
            command, rep->preetham_rmse, rep->preetham_turbidity, rep->hosek_published_rmse,
            rep->hosek_published_turbidity);
    for (int q = 0; q < rep->n_starts; ++q)
      fprintf(stderr, "%s: start '%s' won %d of %d per-elevation fits\n", command,
              rep->start_names[q], rep->start_wins[q], rep->n_elevations * rep->n_channels);
    fprintf(stderr, "%s: elevation fit starts won: through per-elevation fits %d, constant curves %d/%d/%d (of %d channels)\n",
            command, rep->global_start_wins[0], rep->global_start_wins[1], rep->global_start_wins[2],
            rep->global_start_wins[3], rep->n_channels);
    if (rep->global_channels_at_cap > 0)
      fprintf(stderr, "%s: the elevation fit stopped at its %d-iteration cap in %d of %d channels before "
              "converging (usable, not converged; training.elevation_fit_at_iteration_cap)\n", command,
              rep->global_max_iterations, rep->global_channels_at_cap, rep->n_channels);
    fprintf(stderr, "%s: wrote %s (%.2f s fitting)\n", command, out_path, rep->seconds);
  }
  if (status != SF_OK) fprintf(stderr, "%s: %s\n", command, err.message);
  sf_table_set_free(&set);
  free(scene);
  free(atm);
  free(rep);
  free(model);
  free(published);
  return status;
}

int sf_fit_sky_command(sf_sky_form form, int argc, char **argv) {
  char command[64];
  snprintf(command, sizeof command, "skyfit fit %s", sf_sky_form_model_name(form));
  sf_table_cli o;
  sf_table_cli_default(&o);
  const char *out = NULL, *scene = NULL, *tables = NULL, *samples = NULL, *check = NULL;
  int n_elevations = 0, n_theta = 0, n_phi = 0, scale_given = 0, unbounded = 0;
  /* the first option of the tables' fit given (--atmosphere, --resolution,
   * --elevations, ...): --samples and --check take none (they had been
   * accepted and ignored) */
  const char *table_option = NULL;
  double scale = 1.0;
  for (int i = 1; i < argc; ++i) {
    const char *a = argv[i];
    if (strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0) {
      usage(form, stdout);
      return 0;
    }
    int used = sf_table_cli_option(&o, command, argc, argv, &i);
    if (used < 0) return 2;
    if (used && strcmp(a, "--quiet") != 0 && strcmp(a, "--scene") != 0 && !table_option) table_option = a;
    if (used) continue;
    const char *v = sf_cli_value_after(argc, argv, i), *missing = NULL;
    if (strcmp(a, "--unbounded") == 0) {
      unbounded = 1;
    } else if (sf_cli_valued(a, "--out", v, &missing)) {
      out = argv[++i];
    } else if (sf_cli_valued(a, "--scene", v, &missing)) {
      scene = argv[++i];
    } else if (sf_cli_valued(a, "--tables", v, &missing)) {
      tables = argv[++i];
    } else if (sf_cli_valued(a, "--samples", v, &missing)) {
      samples = argv[++i];
    } else if (sf_cli_valued(a, "--check", v, &missing)) {
      check = argv[++i];
    } else if (sf_cli_valued(a, "--scale", v, &missing)) {
      if (parse_double(argv[++i], &scale) || !(scale > 0)) {
        fprintf(stderr, "%s: --scale: expected a positive number, got '%s'\n", command, argv[i]);
        return 2;
      }
      scale_given = 1;
    } else if (sf_cli_valued(a, "--elevations", v, &missing)) {
      char *end;
      long n = strtol(argv[++i], &end, 10);
      if (*end || n < 6 || n > SF_SKY_MAX_ELEVATIONS) {
        fprintf(stderr, "%s: --elevations: expected a whole number in 6..%d, got '%s'\n", command,
                SF_SKY_MAX_ELEVATIONS, argv[i]);
        return 2;
      }
      n_elevations = (int)n;
      if (!table_option) table_option = a;
    } else if (sf_cli_valued(a, "--grid", v, &missing)) {
      if (sf_cli_parse_size_pair(argv[++i], 2, 1024, &n_theta, &n_phi)) {
        fprintf(stderr, "%s: --grid: expected NTxNP with 2..1024 each, got '%s'\n", command, argv[i]);
        return 2;
      }
      if (!table_option) table_option = a;
    } else {
      return sf_cli_bad_option(command, a, missing);
    }
  }
  if (o.scene_path) scene = o.scene_path;   /* parsed by the shared table options */
  if ((check || samples) && table_option) {
    fprintf(stderr, "%s: %s applies to the fit over the reference tables; %s does not take it\n", command,
            table_option, check ? "--check" : "--samples");
    return 2;
  }
  if (check && (out || scene || tables || samples || scale_given || unbounded)) {
    fprintf(stderr, "%s: --check validates a weights file; --out, --scene, --tables, --samples, --scale and "
            "--unbounded do not apply\n", command);
    return 2;
  }
  if (check) return check_weights(form, command, check);
  if (samples) {
    if (out || scene || tables) {
      fprintf(stderr, "%s: --samples fits one sky and prints it; --out/--scene/--tables do not apply\n",
              command);
      return 2;
    }
    return fit_samples(form, command, samples, scale_given, scale, unbounded);
  }
  if (scale_given || unbounded) {
    fprintf(stderr, "%s: --scale and --unbounded apply to --samples only\n", command);
    return 2;
  }
  if (!out) {
    fprintf(stderr, "%s: --out W.json is required (or --samples / --check); see --help\n", command);
    return 2;
  }
  return fit_tables(form, command, &o, scene, tables, out, n_elevations, n_theta, n_phi);
}
