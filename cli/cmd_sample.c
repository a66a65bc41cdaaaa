/* skyfit sample: the reference tables of an atmosphere (SPEC §6, §11) into a
 * folder that is also their cache. Writes DIR/<quantity>-<key>.exr per table
 * and DIR/tables.json, which lists them. Tables already there (same key) are
 * loaded, not recomputed; a corrupt one is reported and recomputed. */
#include "util/make_folders.h"
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include <cjson/cJSON.h>

#include "cli/commands.h"
#include "cli/interrupt_cleanup.h"
#include "cli/option_value.h"
#include "cli/output_file_check.h"
#include "cli/progress_bar.h"
#include "cli/table_options.h"
#include "data/table_set.h"
#include "models/atmosphere_file.h"
#include "util/atomic_file.h"
#include "util/json_exact.h"

#define COMMAND "skyfit sample"

static void sample_usage(FILE *out) {
  fprintf(out,
          "usage: skyfit sample --out DIR [options]\n"
          "\n"
          "Computes the reference tables of an atmosphere: transmittance over (h, mu); single\n"
          "scattering per scattering constituent (without phase function, Bruneton's convention),\n"
          "multiple scattering (orders 2..N) over (h, mu, mu_s, nu); and the indirect ground\n"
          "irradiance over (h, mu_s). Each is a float32 EXR, one channel per colour channel, with\n"
          "the atmosphere, parameterisation and axes in its header, named\n"
          "DIR/<quantity>-<key>.exr, the key hashing everything that determines it; DIR/tables.json\n"
          "lists them. Tables already in DIR are reused; damaged ones are recomputed.\n"
          "With --scene, only the tables the scene asks for, and the scattering tables only over\n"
          "its domain (their axes' ranges, in the EXR headers and tables.json, say which).\n"
          "\n"
          "options:\n"
          "  --out DIR               output (and cache) folder, created if missing; required\n");
  sf_table_cli_help(out);
  fprintf(out, "  --help                  this text\n");
}

/* mkdir -p, then proves DIR/tables.json writable (a temporary file; a
 * folder there is refused now, not after the sampling). */
static int prepare_folder(const char *dir, sf_error *err) {
  if (sf_make_folders(dir, "--out", err)) return SF_ERR_INPUT;
  char path[4096];
  snprintf(path, sizeof path, "%s/tables.json", dir);
  sf_error inner = {0};
  if (sf_atomic_check(path, &inner) != SF_OK) return sf_fail(err, inner.status, "--out: %s", inner.message);
  return SF_OK;
}

static const char *base_name(const char *path) {
  const char *slash = strrchr(path, '/');
  return slash ? slash + 1 : path;
}

/* DIR/tables.json: what was sampled and where each table is. Depends only
 * on the inputs, so reruns write the same bytes. */
static int write_manifest(const char *dir, const sf_atmosphere *atm, const sf_table_set_options *o,
                          const sf_table_set *set, sf_error *err) {
  cJSON *root = cJSON_CreateObject();
  char hash[17];
  sf_atmosphere_hash_hex(atm, hash);
  cJSON_AddNumberToObject(root, "skyfit_tables", 1);
  cJSON_AddStringToObject(root, "code_version", SF_TABLES_CODE_VERSION);
  cJSON_AddStringToObject(root, "atmosphere_name", atm->name);
  cJSON_AddStringToObject(root, "atmosphere_hash", hash);
  cJSON_AddStringToObject(root, "parameterization", sf_parameterization_name(o->kind));
  cJSON *res = cJSON_AddObjectToObject(root, "resolution");
  cJSON_AddNumberToObject(res, "transmittance_mu", o->res.transmittance_mu);
  cJSON_AddNumberToObject(res, "transmittance_h", o->res.transmittance_h);
  cJSON_AddNumberToObject(res, "scattering_h", o->res.scattering_h);
  cJSON_AddNumberToObject(res, "scattering_mu", o->res.scattering_mu);
  cJSON_AddNumberToObject(res, "scattering_mu_s", o->res.scattering_mu_s);
  cJSON_AddNumberToObject(res, "scattering_nu", o->res.scattering_nu);
  cJSON_AddNumberToObject(res, "irradiance_mu_s", o->res.irradiance_mu_s);
  cJSON_AddNumberToObject(res, "irradiance_h", o->res.irradiance_h);
  cJSON_AddNumberToObject(root, "orders", o->orders);
  cJSON_AddNumberToObject(root, "stop_fraction", o->stop_fraction);
  if (o->has_domain) {
    /* the scene's domain as the scattering tables cover it (altitudes
     * clamped into the atmosphere) */
    const sf_table_params *p = &set->params;
    cJSON *d = cJSON_AddObjectToObject(root, "domain");
    cJSON_AddNumberToObject(d, "h_min_km", p->h_min_km);
    cJSON_AddNumberToObject(d, "h_max_km", p->h_max_km);
    cJSON_AddNumberToObject(d, "mu_min", o->kind == SF_PARAM_LEENMAN ? p->mu_min : o->domain.mu_min);
    cJSON_AddNumberToObject(d, "mu_s_min", p->mu_s_min);
    cJSON_AddNumberToObject(d, "mu_s_max", p->mu_s_max);
    cJSON_AddBoolToObject(d, "sky_only", o->domain.sky_only);
  }
  cJSON *quantities = cJSON_AddArrayToObject(root, "quantities");
  cJSON_AddItemToArray(quantities, cJSON_CreateString("transmittance"));
  if (!o->transmittance_only) cJSON_AddItemToArray(quantities, cJSON_CreateString("sky_radiance"));
  cJSON *tables = cJSON_AddArrayToObject(root, "tables");
  for (int t = 0; t < set->n_tables; ++t) {
    const sf_table_desc *desc = &set->tables[t]->desc;
    cJSON *e = cJSON_CreateObject();
    cJSON_AddStringToObject(e, "quantity", desc->quantity);
    cJSON_AddStringToObject(e, "file", base_name(set->paths[t]));
    cJSON_AddStringToObject(e, "content_hash", desc->content_hash);
    cJSON *axes = cJSON_AddArrayToObject(e, "axes");
    for (int k = 0; k < desc->n_axes; ++k) {
      cJSON *a = cJSON_CreateObject();
      cJSON_AddStringToObject(a, "name", desc->axes[k].name);
      cJSON_AddNumberToObject(a, "size", desc->axes[k].size);
      cJSON_AddNumberToObject(a, "min", desc->axes[k].min);
      cJSON_AddNumberToObject(a, "max", desc->axes[k].max);
      cJSON_AddStringToObject(a, "mapping", desc->axes[k].mapping);
      cJSON_AddItemToArray(axes, a);
    }
    cJSON_AddItemToArray(tables, e);
  }
  char path[4096];
  snprintf(path, sizeof path, "%s/tables.json", dir);
  int status = sf_json_write_exact(root, path, err);
  cJSON_Delete(root);
  return status;
}

/* What an interrupted sample leaves in its folder: the temporary of the
 * table it was writing. */
static void remove_stale_tables(void *out_dir) { sf_atomic_remove_stale_in(out_dir); }

int sf_cmd_sample(int argc, char **argv) {
  sf_table_cli o;
  sf_table_cli_default(&o);
  const char *out_dir = NULL;
  for (int i = 1; i < argc; ++i) {
    const char *a = argv[i];
    if (strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0) {
      sample_usage(stdout);
      return 0;
    }
    int used = sf_table_cli_option(&o, COMMAND, argc, argv, &i);
    if (used < 0) return 2;
    if (used) continue;
    const char *missing = NULL;
    if (sf_cli_valued(a, "--out", sf_cli_value_after(argc, argv, i), &missing)) {
      out_dir = argv[++i];
    } else {
      return sf_cli_bad_option(COMMAND, a, missing);
    }
  }
  if (!out_dir) {
    fprintf(stderr, "%s: --out DIR is required\n", COMMAND);
    return 2;
  }
  sf_atmosphere atm;
  int rc = sf_table_cli_atmosphere(&o, COMMAND, &atm);
  if (rc) return rc;
  /* DIR/tables.json is none of the inputs: `--out d --atmosphere
   * d/tables.json` had replaced the atmosphere by the list, exit 0 */
  char manifest[4096];
  snprintf(manifest, sizeof manifest, "%s/tables.json", out_dir);
  const char *inputs[2] = {o.atmosphere_path, o.scene_path};
  const char *clash = sf_cli_same_as_any(manifest, inputs, 2);
  if (clash) {
    fprintf(stderr, "%s: --out %s: its tables.json would overwrite the input %s; give another folder\n", COMMAND,
            out_dir, clash);
    return 2;
  }
  sf_error err = {0};
  if (sf_table_set_check(&atm, &o.set, &err) != SF_OK) {
    fprintf(stderr, "%s: %s\n", COMMAND, err.message);
    return err.status;
  }
  /* Ctrl-C, SIGTERM or SIGHUP leave no table half written
   * (cli/interrupt_cleanup.h): a SIGTERM had left one. Supervised before
   * the folder's write probe, whose temporary a SIGTERM had left too. */
  sf_cli_supervise(remove_stale_tables, (void *)out_dir);
  if (prepare_folder(out_dir, &err) != SF_OK) {
    fprintf(stderr, "%s: %s\n", COMMAND, err.message);
    return err.status;
  }

  sf_progress_bar bar;
  sf_progress_bar_init(&bar, stderr, !o.quiet);
  bar.note_prefix = COMMAND;
  o.set.cache_dir = out_dir;
  o.set.run.progress = sf_progress_bar_update;
  o.set.run.progress_ctx = &bar;
  if (!o.quiet) {
    o.set.note = sf_progress_bar_note;
    o.set.note_ctx = &bar;
  }
  sf_table_set set;
  int status = sf_table_set_make(&set, &atm, &o.set, &err);
  sf_progress_bar_finish(&bar);
  if (status == SF_OK) status = write_manifest(out_dir, &atm, &o.set, &set, &err);
  if (status != SF_OK) {
    fprintf(stderr, "%s: %s\n", COMMAND, err.message);
    sf_table_set_free(&set);
    return status;
  }
  if (!o.quiet) {
    int cached = 0;
    for (int t = 0; t < set.n_tables; ++t) cached += set.from_cache[t];
    for (int k = 2; set.multiple_computed && k <= set.report.highest_order; ++k) {
      if (isfinite(set.report.remaining_fraction[k]))
        fprintf(stderr, "%s: scattering order %d adds %.3g of the sky radiance so far, the orders left about %.3g "
                "(in the channel where most)\n", COMMAND, k, set.report.added_fraction[k],
                set.report.remaining_fraction[k]);
      else
        fprintf(stderr, "%s: scattering order %d adds %.3g of the sky radiance so far (in the channel where most)\n",
                COMMAND, k, set.report.added_fraction[k]);
    }
    fprintf(stderr, "%s: %d tables in %s (%d computed, %d from the cache); list in %s/tables.json\n",
            COMMAND, set.n_tables, out_dir, set.n_tables - cached, cached, out_dir);
  }
  sf_table_set_free(&set);
  return 0;
}
