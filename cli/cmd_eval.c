/* skyfit eval QUANTITY: reference quantities at points read as CSV on stdin
 * (SPEC §11), or with --model a fitted model's (cli/eval_model.h). All
 * input is read and validated first; a bad row exits 2 with nothing on
 * stdout. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli/atmosphere_warnings.h"
#include "cli/commands.h"
#include "cli/csv_points.h"
#include "cli/cmd_eval_tables.h"
#include "cli/eval_model.h"
#include "cli/option_value.h"
#include "cli/output_file_check.h"
#include "models/atmosphere_file.h"
#include "models/optical_depth.h"
#include "models/phase.h"
#include "models/single_scattering.h"
#include "models/view_ray.h"

typedef enum quantity { Q_OPTICAL_DEPTH, Q_TRANSMITTANCE, Q_SINGLE_SCATTERING, Q_SKY_RADIANCE } quantity;

typedef struct eval_options {
  quantity what;
  const char *atmosphere_path;
  const char *model_path;   /* --model: a fitted model instead of the reference */
  const char *transmittance_path;   /* --transmittance-model: mlp-scattering's segments */
  int phase;
  sf_ray_end end;
  double distance;      /* < 0: none */
  int quiet;            /* no note on stderr (points outside a model's domain) */
} eval_options;

static const char *const ray_columns[] = {"h_km", "mu", NULL};
static const char *const sun_columns[] = {"h_km", "mu", "mu_s", "nu", NULL};

static void eval_usage(FILE *out) {
  fprintf(out,
          "usage: skyfit eval optical_depth|transmittance|single_scattering [options] < points.csv\n"
          "       skyfit eval transmittance|sky_radiance --model W.json [options] < points.csv\n"
          "       (multiple_scattering and sky_radiance of the reference tables:\n"
          "        skyfit eval sky_radiance --help)\n"
          "\n"
          "Reads CSV on stdin: a header naming the columns, then one point per row.\n"
          "  optical_depth, transmittance: h_km,mu\n"
          "  single_scattering, sky_radiance: h_km,mu,mu_s,nu\n"
          "h_km is the viewer altitude above the ground (may exceed the top of the\n"
          "atmosphere), mu the cosine of the view zenith angle, mu_s of the sun zenith angle,\n"
          "nu of the view-sun angle (clamped to what mu and mu_s allow).\n"
          "Writes CSV on stdout: the input columns, then\n"
          "  optical_depth:     one column per constituent (density integral, km)\n"
          "  transmittance:     T_<channel>\n"
          "  single_scattering: <constituent>_<channel> per scattering constituent\n"
          "  sky_radiance:      L_<channel>\n"
          "\n"
          "options:\n"
          "  --atmosphere FILE  atmosphere JSON (default: the built-in Earth, SPEC §4)\n"
          "  --model W.json     a fitted model's values instead of the reference's, in double, for\n"
          "                     the atmosphere it was fitted for (its weights file, SPEC §8):\n"
          "                     transmittance: sigmoid, mlp-transmittance; sky_radiance:\n"
          "                     mlp-scattering, preetham, hosek (a viewer on the ground: h_km is\n"
          "                     not used, and a point off the ground counts as outside the\n"
          "                     domain). Points outside the domain it was fitted on are counted\n"
          "                     on stderr (their values are extrapolations)\n"
          "  --phase            multiply single scattering by the phase function at nu\n"
          "  --to nearest|top   ray end: the ground or the top, whichever comes first\n"
          "                     (default), or the top (rays that hit the ground are an error)\n"
          "  --to-distance D    the segment from the viewer to distance D km along the ray\n"
          "                     (--to top: the reference, sigmoid or mlp-transmittance;\n"
          "                     --to-distance: these and mlp-scattering with\n"
          "                     --transmittance-model)\n"
          "  --transmittance-model T.json\n"
          "                     the mlp-transmittance network (the same atmosphere) that an\n"
          "                     mlp-scattering model's segments take (seed 000 eq. 44)\n"
          "  --quiet            no notes on stderr (errors are still reported)\n"
          "  --help             this text\n");
}

static int parse_options(int argc, char **argv, eval_options *o) {
  memset(o, 0, sizeof *o);
  o->distance = -1.0;
  int to_given = 0, distance_given = 0;
  const char *q = NULL;
  for (int i = 1; i < argc; ++i) {
    const char *a = argv[i];
    const char *v = sf_cli_value_after(argc, argv, i), *missing = NULL;
    if (strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0) {
      eval_usage(stdout);
      return 0;
    } else if (sf_cli_valued(a, "--atmosphere", v, &missing)) {
      o->atmosphere_path = argv[++i];
    } else if (sf_cli_valued(a, "--model", v, &missing)) {
      o->model_path = argv[++i];
    } else if (sf_cli_valued(a, "--transmittance-model", v, &missing)) {
      o->transmittance_path = argv[++i];
    } else if (strcmp(a, "--phase") == 0) {
      o->phase = 1;
    } else if (strcmp(a, "--quiet") == 0) {
      o->quiet = 1;
    } else if (sf_cli_valued(a, "--to", v, &missing)) {
      ++i;
      to_given = 1;
      if (strcmp(v, "top") == 0) o->end = SF_RAY_END_TOP;
      else if (strcmp(v, "nearest") == 0) o->end = SF_RAY_END_NEAREST;
      else {
        fprintf(stderr, "skyfit eval: --to: expected 'nearest' or 'top', got '%s'\n", v);
        return 2;
      }
    } else if (sf_cli_valued(a, "--to-distance", v, &missing)) {
      char *end;
      distance_given = 1;
      o->distance = strtod(argv[++i], &end);
      if (end == argv[i] || *end != '\0' || !isfinite(o->distance) || o->distance < 0.0) {   /* "" had read as 0 */
        fprintf(stderr, "skyfit eval: --to-distance: expected a distance >= 0 in km, got '%s'\n",
                argv[i]);
        return 2;
      }
    } else if (strcmp(a, "--tables") == 0 || strcmp(a, "--scene") == 0 || strcmp(a, "--resolution") == 0) {
      /* "unknown option" had said nothing of why (--scene: it is one of
       * sky_radiance's options, so it looked like a typo) */
      fprintf(stderr, "skyfit eval: %s: the reference's multiple_scattering and sky_radiance read tables (of a "
              "scene's domain, at a resolution); a fitted model (--model) and the other quantities do not\n", a);
      return 2;
    } else if (a[0] == '-') {
      return sf_cli_bad_option("skyfit eval", a, missing);
    } else if (!q) {
      q = a;
    } else {
      fprintf(stderr, "skyfit eval: unexpected argument '%s'\n", a);
      return 2;
    }
  }
  if (to_given && distance_given) {
    fprintf(stderr, "skyfit eval: --to and --to-distance both say where the ray ends: give one\n");
    return 2;
  }
  if (!q) {
    fprintf(stderr, "skyfit eval: which quantity? optical_depth, transmittance, single_scattering, "
                    "multiple_scattering or sky_radiance\n");
    eval_usage(stderr);
    return 2;
  }
  if (strcmp(q, "optical_depth") == 0) o->what = Q_OPTICAL_DEPTH;
  else if (strcmp(q, "transmittance") == 0) o->what = Q_TRANSMITTANCE;
  else if (strcmp(q, "single_scattering") == 0) o->what = Q_SINGLE_SCATTERING;
  else if (strcmp(q, "sky_radiance") == 0 && o->model_path) o->what = Q_SKY_RADIANCE;
  else if (strcmp(q, "multiple_scattering") == 0 && o->model_path) {   /* it had been an "unknown quantity" */
    fprintf(stderr, "skyfit eval: --model: fitted models give transmittance or sky_radiance, not %s\n", q);
    return 2;
  } else {
    fprintf(stderr,
            "skyfit eval: unknown quantity '%s' (optical_depth, transmittance, single_scattering, "
            "multiple_scattering, sky_radiance)\n",
            q);
    return 2;
  }
  if (o->phase && o->what != Q_SINGLE_SCATTERING) {
    fprintf(stderr, "skyfit eval: --phase applies to single_scattering only\n");
    return 2;
  }
  if (o->model_path && o->what != Q_TRANSMITTANCE && o->what != Q_SKY_RADIANCE) {
    fprintf(stderr, "skyfit eval: --model: fitted models give transmittance or sky_radiance, not %s\n", q);
    return 2;
  }
  if (o->transmittance_path && !(o->model_path && o->what == Q_SKY_RADIANCE && distance_given)) {
    fprintf(stderr, "skyfit eval: --transmittance-model: for sky_radiance --model (mlp-scattering) with "
                    "--to-distance only\n");
    return 2;
  }
  if (o->model_path && o->atmosphere_path) {
    fprintf(stderr, "skyfit eval: --model evaluates the atmosphere its weights file holds; leave out --atmosphere\n");
    return 2;
  }
  return -1;   /* go on */
}

/* Output column names after the input columns. Returns their count. */
static int output_columns(const sf_atmosphere *atm, quantity what, char names[][64]) {
  int n = 0;
  if (what == Q_OPTICAL_DEPTH) {
    for (int i = 0; i < atm->n_constituents; ++i)
      snprintf(names[n++], 64, "%s", atm->constituents[i].name);
  } else if (what == Q_TRANSMITTANCE || what == Q_SKY_RADIANCE) {
    for (int ch = 0; ch < atm->n_channels; ++ch)
      snprintf(names[n++], 64, "%s_%s", what == Q_TRANSMITTANCE ? "T" : "L", atm->channel_names[ch]);
  } else {
    for (int i = 0; i < atm->n_constituents; ++i) {
      if (!sf_constituent_scatters(&atm->constituents[i], atm->n_channels)) continue;
      for (int ch = 0; ch < atm->n_channels; ++ch)
        snprintf(names[n++], 64, "%s_%s", atm->constituents[i].name, atm->channel_names[ch]);
    }
  }
  return n;
}

/* Checks the ranges of one row and builds its view ray. */
/* A row's ray: for a viewer above the top, from where it enters
 * (models/view_ray.h), with the sun's cosine there. */
typedef struct eval_ray {
  sf_view_ray ray;
  double mu_s;
} eval_ray;

static int prepare_row(const sf_atmosphere *atm, const eval_options *o, const sf_csv_points *pts,
                       long row, eval_ray *ray, sf_error *err) {
  const double *v = pts->values + row * pts->n_columns;
  long line = sf_csv_points_line(pts, row);   /* not row + 2: blank lines are skipped */
  static const char *const unit_columns[] = {"mu", "mu_s", "nu"};
  for (int k = 0; k < 3; ++k) {
    int c = sf_csv_points_column(pts, unit_columns[k]);
    if (c >= 0 && (v[c] < -1.0 || v[c] > 1.0))
      return sf_fail(err, SF_ERR_INPUT, "stdin: row %ld, column %s: %s is outside [-1, 1]", line,
                     unit_columns[k], pts->fields[row * pts->n_columns + c]);
  }
  double h = v[sf_csv_points_column(pts, "h_km")];
  if (h < 0.0)
    return sf_fail(err, SF_ERR_INPUT, "stdin: row %ld, column h_km: %s is below the ground", line,
                   pts->fields[row * pts->n_columns + sf_csv_points_column(pts, "h_km")]);
  const char *why = "";
  int c_mu_s = sf_csv_points_column(pts, "mu_s"), c_nu = sf_csv_points_column(pts, "nu");
  double mu = v[sf_csv_points_column(pts, "mu")], mu_s = c_mu_s >= 0 ? v[c_mu_s] : 0.0;
  double nu = c_nu >= 0 ? sf_clamp_nu(mu, mu_s, v[c_nu]) : 0.0;
  if (sf_view_ray_make_at_entry(atm, h, mu, mu_s, nu, o->end, o->distance, &ray->ray, &ray->mu_s, &why))
    return sf_fail(err, SF_ERR_INPUT, "stdin: row %ld: %s", line, why);
  return 0;
}

/* A row as a fitted model takes it (cli/eval_model.h): h_km, mu, then mu_s,
 * nu (0 where the quantity has no such column). */
static void model_point(const sf_csv_points *pts, long row, double p[4]) {
  static const char *const names[] = {"h_km", "mu", "mu_s", "nu"};
  const double *v = pts->values + row * pts->n_columns;
  for (int k = 0; k < 4; ++k) {
    int c = sf_csv_points_column(pts, names[k]);
    p[k] = c >= 0 ? v[c] : 0.0;
  }
}

static void evaluate_row(const sf_atmosphere *atm, const eval_options *o, const sf_eval_model *model,
                         const sf_csv_points *pts, long row, const eval_ray *er, double *out) {
  const sf_view_ray *ray = &er->ray;
  const double *v = pts->values + row * pts->n_columns;
  if (model) {
    double p[4];
    model_point(pts, row, p);
    sf_eval_model_values(model, p, o->distance, out);
    return;
  }
  double depth[SF_MAX_CONSTITUENTS];
  if (o->what != Q_SINGLE_SCATTERING) {
    sf_optical_depth_segment(atm, ray->r, ray->mu, ray->t0, ray->t1, depth);
    if (o->what == Q_OPTICAL_DEPTH)
      memcpy(out, depth, sizeof(double) * (size_t)atm->n_constituents);
    else
      sf_transmittance_from_depth(atm, depth, out);
    return;
  }
  double mu_s = v[sf_csv_points_column(pts, "mu_s")], nu = v[sf_csv_points_column(pts, "nu")];
  double clamped_nu = sf_clamp_nu(v[sf_csv_points_column(pts, "mu")], mu_s, nu);
  double all[SF_MAX_CONSTITUENTS * SF_MAX_CHANNELS];
  sf_single_scattering(atm, ray, er->mu_s, clamped_nu, all);
  int n = 0;
  for (int i = 0; i < atm->n_constituents; ++i) {
    const sf_constituent *c = &atm->constituents[i];
    if (!sf_constituent_scatters(c, atm->n_channels)) continue;
    double phase = o->phase ? sf_phase_value(&c->phase, clamped_nu) : 1.0;
    for (int ch = 0; ch < atm->n_channels; ++ch) out[n++] = all[i * atm->n_channels + ch] * phase;
  }
}

/* Points that lie outside the domain the model was fitted on. */
static long count_outside(const sf_eval_model *model, const sf_csv_points *pts) {
  long n = 0;
  for (long row = 0; row < pts->n_rows; ++row) {
    double p[4];
    model_point(pts, row, p);
    n += sf_eval_model_outside(model, p);
  }
  return n;
}

static void free_model(sf_eval_model *m) {
  if (!m) return;
  sf_eval_model_free(m);
  free(m);
}

static int has_model_option(int argc, char **argv) {
  for (int i = 1; i < argc; ++i)
    if (strcmp(argv[i], "--model") == 0) return 1;
  return 0;
}

int sf_cmd_eval(int argc, char **argv) {
  /* multiple_scattering and sky_radiance of the reference are read from
   * tables (issue 3); sky_radiance --model is a fitted model's, here. */
  for (int i = 1; i < argc; ++i)
    if (sf_eval_tables_handles(argv[i]) && !has_model_option(argc, argv)) return sf_cmd_eval_tables(argc, argv);
  eval_options o;
  int rc = parse_options(argc, argv, &o);
  if (rc >= 0) return rc;

  sf_error err;
  sf_error_clear(&err);
  sf_atmosphere atm;
  sf_eval_model *fitted = NULL;   /* --model */
  if (o.model_path) {
    fitted = calloc(1, sizeof *fitted);
    if (!fitted) {
      fprintf(stderr, "skyfit eval: out of memory\n");
      return 1;
    }
    if (sf_eval_model_load(o.model_path, o.what == Q_SKY_RADIANCE ? "sky_radiance" : "transmittance", fitted, &err) ||
        (o.transmittance_path && sf_eval_model_load_transmittance(fitted, o.transmittance_path, &err)) ||
        sf_eval_model_check_ray(fitted, o.end, o.distance, &err)) {
      fprintf(stderr, "skyfit eval: %s\n", err.message);
      free_model(fitted);
      return err.status;
    }
    atm = fitted->atmosphere;
  } else if (o.atmosphere_path) {
    if (sf_atmosphere_load_file(o.atmosphere_path, &atm, &err)) {
      fprintf(stderr, "skyfit eval: %s\n", err.message);
      return err.status;
    }
    sf_cli_warn_atmosphere_units("skyfit eval", o.atmosphere_path, &atm);
  } else {
    sf_atmosphere_default(&atm);
  }

  sf_csv_points pts;
  const char *const *columns = o.what == Q_SINGLE_SCATTERING || o.what == Q_SKY_RADIANCE ? sun_columns : ray_columns;
  if (sf_csv_points_read(stdin, "stdin", columns, columns, &pts, &err)) {
    fprintf(stderr, "skyfit eval: %s\n", err.message);
    free_model(fitted);
    return err.status;
  }
  static char names[SF_MAX_CONSTITUENTS * SF_MAX_CHANNELS][64];
  int n_out = output_columns(&atm, o.what, names);
  eval_ray *rays = malloc(sizeof(eval_ray) * (size_t)(pts.n_rows ? pts.n_rows : 1));
  double *results = malloc(sizeof(double) * (size_t)((pts.n_rows ? pts.n_rows : 1) * (n_out ? n_out : 1)));
  if (!rays || !results) {
    fprintf(stderr, "skyfit eval: out of memory for %ld points\n", pts.n_rows);
    free(rays), free(results), sf_csv_points_free(&pts);
    free_model(fitted);
    return 1;
  }
  for (long row = 0; row < pts.n_rows; ++row)
    if (prepare_row(&atm, &o, &pts, row, &rays[row], &err)) {
      fprintf(stderr, "skyfit eval: %s\n", err.message);
      free(rays), free(results), sf_csv_points_free(&pts);
      free_model(fitted);
      return err.status;
    }

  /* Rows are independent: the thread count cannot change any value. */
#pragma omp parallel for schedule(dynamic, 16)
  for (long row = 0; row < pts.n_rows; ++row)
    evaluate_row(&atm, &o, fitted, &pts, row, &rays[row], results + row * n_out);
  /* Finite inputs can still overflow: a weights file's extreme (finite)
   * parameters, an atmosphere's sun of 1e308. Such a value is not printed
   * (it had been, as inf, with exit 0): the input is at fault. */
  long bad_row = -1;
  int bad_column = 0;
  for (long row = 0; row < pts.n_rows && bad_row < 0; ++row)
    for (int k = 0; k < n_out; ++k)
      if (!isfinite(results[row * n_out + k])) {
        bad_row = row;
        bad_column = k;
        break;
      }
  if (bad_row >= 0) {
    char point[256] = "";
    for (int c = 0, w = 0; c < pts.n_columns && w >= 0 && (size_t)w < sizeof point; ++c)
      w += snprintf(point + w, sizeof point - (size_t)w, "%s%s=%s", c ? ", " : "", pts.column_names[c],
                    pts.fields[bad_row * pts.n_columns + c]);
    const char *source = o.model_path ? o.model_path : o.atmosphere_path ? o.atmosphere_path : "the built-in atmosphere";
    fprintf(stderr, "skyfit eval: %s: %s is not finite at point %ld (%s): %s overflow there; nothing written\n",
            source, names[bad_column], bad_row + 1, point,
            o.model_path ? "the model's parameters" : "the atmosphere's values");
    free(rays), free(results), sf_csv_points_free(&pts);
    free_model(fitted);
    return 2;
  }
  long n_outside = fitted ? count_outside(fitted, &pts) : 0;
  if (n_outside > 0 && !o.quiet) {
    const sf_scene_domain *d = &fitted->domain;
    char mu_s[64] = "";
    if (o.what == Q_SKY_RADIANCE) snprintf(mu_s, sizeof mu_s, ", mu_s %g..%g", d->mu_s_min, d->mu_s_max);
    fprintf(stderr,
            "skyfit eval: %s: %ld of %ld points lie outside the domain the model was fitted on (h_km %g..%g, "
            "mu %g..%g%s); its values there are extrapolations\n",
            o.model_path, n_outside, pts.n_rows, d->h_min_km, d->h_max_km, d->mu_min, d->mu_max, mu_s);
  }

  for (int c = 0; c < pts.n_columns; ++c) printf("%s%s", c ? "," : "", pts.column_names[c]);
  for (int k = 0; k < n_out; ++k) printf(",%s", names[k]);
  printf("\n");
  for (long row = 0; row < pts.n_rows; ++row) {
    for (int c = 0; c < pts.n_columns; ++c)
      printf("%s%s", c ? "," : "", pts.fields[row * pts.n_columns + c]);
    for (int k = 0; k < n_out; ++k) printf(",%.17g", results[row * n_out + k]);
    printf("\n");
  }
  free(rays);
  free(results);
  sf_csv_points_free(&pts);
  free_model(fitted);
  return sf_cli_stdout_written("skyfit eval");
}
