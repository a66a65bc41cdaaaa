/* skyfit eval multiple_scattering | sky_radiance (SPEC §11): evaluates the
 * reference tables (loaded from --tables DIR, or computed and stored there,
 * or computed in memory) at the CSV points on stdin, with multilinear
 * interpolation in the tables' parameterisation. All input is read and
 * checked first; a bad row exits 2 with nothing on stdout. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli/cmd_eval_tables.h"
#include "cli/csv_points.h"
#include "cli/interrupt_cleanup.h"
#include "cli/option_value.h"
#include "cli/output_file_check.h"
#include "cli/progress_bar.h"
#include "cli/table_options.h"
#include "data/sky_lookup.h"
#include "data/table_set.h"
#include "models/single_scattering.h"

#define COMMAND "skyfit eval"

int sf_eval_tables_handles(const char *quantity) {
  return strcmp(quantity, "multiple_scattering") == 0 || strcmp(quantity, "sky_radiance") == 0;
}

static void usage(FILE *out) {
  fprintf(out,
          "usage: skyfit eval multiple_scattering|sky_radiance [options] < points.csv\n"
          "\n"
          "Reads CSV on stdin with the columns h_km,mu,mu_s,nu (a viewer at altitude h_km above\n"
          "the ground, possibly above the atmosphere; view, sun and view-sun cosines, nu clamped\n"
          "to what mu and mu_s allow) and writes CSV on stdout: the input columns, then\n"
          "  multiple_scattering: multiple_<channel>, scattering orders 2..N\n"
          "  sky_radiance:        L_<channel>, single scattering of every constituent times its\n"
          "                       phase function plus multiple scattering (no direct sun, no ground)\n"
          "interpolated in the reference tables (skyfit sample). A viewer above the atmosphere\n"
          "sees from where the ray enters it; a ray that never enters gives 0.\n"
          "A fitted model's sky radiance instead: skyfit eval sky_radiance --model W.json\n"
          "(skyfit eval --help).\n"
          "\n"
          "options:\n"
          "  --tables DIR            load the tables from DIR (skyfit sample --out DIR); those\n"
          "                          missing are computed and stored there. Without it they are\n"
          "                          computed in memory (about 20 s on 2 cores at the default\n"
          "                          resolution)\n");
  sf_table_cli_help(out);
  fprintf(out, "  --help                  this text\n");
}

static int check_rows(const sf_csv_points *pts, sf_error *err) {
  static const char *const unit[] = {"mu", "mu_s", "nu"};
  int h = sf_csv_points_column(pts, "h_km");
  for (long row = 0; row < pts->n_rows; ++row) {
    const double *v = pts->values + row * pts->n_columns;
    long line = sf_csv_points_line(pts, row);   /* not row + 2: blank lines are skipped */
    for (int k = 0; k < 3; ++k) {
      int c = sf_csv_points_column(pts, unit[k]);
      if (v[c] < -1.0 || v[c] > 1.0)
        return sf_fail(err, SF_ERR_INPUT, "stdin: row %ld, column %s: %s is outside [-1, 1]", line, unit[k],
                       pts->fields[row * pts->n_columns + c]);
    }
    if (v[h] < 0.0)
      return sf_fail(err, SF_ERR_INPUT, "stdin: row %ld, column h_km: %s is below the ground", line,
                     pts->fields[row * pts->n_columns + h]);
  }
  return SF_OK;
}

int sf_cmd_eval_tables(int argc, char **argv) {
  sf_table_cli o;
  sf_table_cli_default(&o);
  const char *quantity = NULL, *tables_dir = NULL;
  for (int i = 1; i < argc; ++i) {
    const char *a = argv[i];
    if (strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0) {
      usage(stdout);
      return 0;
    }
    int used = sf_table_cli_option(&o, COMMAND, argc, argv, &i);
    if (used < 0) return 2;
    if (used) continue;
    const char *missing = NULL;
    if (sf_cli_valued(a, "--tables", sf_cli_value_after(argc, argv, i), &missing)) {
      tables_dir = argv[++i];
    } else if (strcmp(a, "--to") == 0 || strcmp(a, "--to-distance") == 0) {
      /* the tables hold whole rays (SPEC §6); "unknown option" had said
       * nothing of why */
      fprintf(stderr,
              "%s: %s: the scattering tables hold whole rays (to the ground or out of the atmosphere), not "
              "segments (the emitted networks give them: skyfit_mlp_sky_radiance_segment)\n",
              COMMAND, a);
      return 2;
    } else if (a[0] == '-') {
      return sf_cli_bad_option(COMMAND, a, missing);
    } else if (!quantity) {
      quantity = a;
    } else {
      fprintf(stderr, "%s: unexpected argument '%s'\n", COMMAND, a);
      return 2;
    }
  }
  if (!quantity || !sf_eval_tables_handles(quantity)) {
    fprintf(stderr, "%s: expected the quantity multiple_scattering or sky_radiance, got '%s'\n", COMMAND,
            quantity ? quantity : "");
    return 2;
  }
  int sky = strcmp(quantity, "sky_radiance") == 0;
  sf_atmosphere atm;
  int rc = sf_table_cli_atmosphere(&o, COMMAND, &atm);
  if (rc) return rc;
  if (o.set.transmittance_only) {
    fprintf(stderr, "%s: scene %s asks for transmittance only: it has no scattering tables to evaluate\n",
            COMMAND, o.scene_path);
    return 2;
  }
  sf_error err = {0};
  if (sf_table_set_check(&atm, &o.set, &err) != SF_OK) {
    fprintf(stderr, "%s: %s\n", COMMAND, err.message);
    return 2;
  }
  static const char *const columns[] = {"h_km", "mu", "mu_s", "nu", NULL};
  sf_csv_points pts;
  if (sf_csv_points_read(stdin, "stdin", columns, columns, &pts, &err) != SF_OK) {
    fprintf(stderr, "%s: %s\n", COMMAND, err.message);
    return err.status;
  }
  if (check_rows(&pts, &err) != SF_OK) {
    fprintf(stderr, "%s: %s\n", COMMAND, err.message);
    sf_csv_points_free(&pts);
    return 2;
  }

  sf_progress_bar bar;
  sf_progress_bar_init(&bar, stderr, !o.quiet);
  bar.note_prefix = COMMAND;
  o.set.cache_dir = tables_dir;
  o.set.run.progress = sf_progress_bar_update;
  o.set.run.progress_ctx = &bar;
  if (!o.quiet) {
    o.set.note = sf_progress_bar_note;
    o.set.note_ctx = &bar;
  }
  /* a signal leaves no table's temporary in the tables' folder
   * (cli/interrupt_cleanup.h); stdin is read, so the work process needs
   * none of it */
  sf_cli_outputs outputs = {0};
  sf_cli_outputs_add_folder(&outputs, tables_dir);
  if (tables_dir) sf_cli_supervise_outputs(&outputs);
  sf_table_set set;
  int status = sf_table_set_make(&set, &atm, &o.set, &err);
  sf_progress_bar_finish(&bar);
  if (status != SF_OK) {
    fprintf(stderr, "%s: %s\n", COMMAND, err.message);
    sf_csv_points_free(&pts);
    return status;
  }
  sf_sky_tables sky_tables;
  sf_sky_tables_of_set(&sky_tables, &atm, &set);
  int c_h = sf_csv_points_column(&pts, "h_km"), c_mu = sf_csv_points_column(&pts, "mu");
  int c_s = sf_csv_points_column(&pts, "mu_s"), c_nu = sf_csv_points_column(&pts, "nu");
  /* A scene's tables hold its domain only; a lookup outside it returns the
   * nearest entry, not the sky there (the sun below a scene's lowest sun
   * had given that lowest sun's sky), so such points are counted, where
   * the lookup reads the tables: a viewer above the top where its ray
   * enters, with the cosines there (a ray that never enters is 0, exact). */
  long n_outside = 0;
  for (long row = 0; o.scene_path && row < pts.n_rows; ++row) {
    const double *v = pts.values + row * pts.n_columns;
    double r, mu = v[c_mu], mu_s = v[c_s];
    if (!sf_sky_enter_atmosphere(&atm, v[c_h], &r, &mu, &mu_s, sf_clamp_nu(v[c_mu], v[c_s], v[c_nu]))) continue;
    n_outside += sf_scene_domain_outside(&o.scene_domain, atm.top_radius_km - atm.bottom_radius_km,
                                         r - atm.bottom_radius_km, mu, 1, mu_s);
  }
  if (n_outside > 0 && !o.quiet) {
    const sf_scene_domain *d = &o.scene_domain;
    fprintf(stderr,
            "%s: %ld of %ld points lie outside scene %s's domain (h_km %g..%g, mu %g..%g, mu_s %g..%g), which "
            "its tables cover; their values are the tables' at its edge, not the sky there (evaluate them "
            "without --scene)\n",
            COMMAND, n_outside, pts.n_rows, o.scene_path, d->h_min_km, d->h_max_km, d->mu_min, d->mu_max,
            d->mu_s_min, d->mu_s_max);
  }
  for (int c = 0; c < pts.n_columns; ++c) printf("%s%s", c ? "," : "", pts.column_names[c]);
  for (int ch = 0; ch < atm.n_channels; ++ch) printf(",%s%s", sky ? "L_" : "multiple_", atm.channel_names[ch]);
  printf("\n");
  for (long row = 0; row < pts.n_rows; ++row) {
    const double *v = pts.values + row * pts.n_columns;
    sf_sky_sample sample;
    sf_sky_lookup(&sky_tables, v[c_h], v[c_mu], v[c_s], v[c_nu], &sample);
    for (int c = 0; c < pts.n_columns; ++c) printf("%s%s", c ? "," : "", pts.fields[row * pts.n_columns + c]);
    for (int ch = 0; ch < atm.n_channels; ++ch) printf(",%.9g", sky ? sample.radiance[ch] : sample.multiple[ch]);
    printf("\n");
  }
  sf_table_set_free(&set);
  sf_csv_points_free(&pts);
  return sf_cli_stdout_written(COMMAND);
}
