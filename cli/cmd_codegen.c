/* skyfit codegen: GLSL and C headers for fitted models (weights files) and
 * the analytic baselines of SPEC §7.6 (SPEC §9). Everything is read and
 * rendered before anything is written; both files are written atomically. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli/atmosphere_warnings.h"
#include "cli/commands.h"
#include "cli/interrupt_cleanup.h"
#include "cli/option_value.h"
#include "cli/output_file_check.h"
#include "codegen/baseline_part.h"
#include "codegen/codegen_file.h"
#include "codegen/fitted_part.h"
#include "models/atmosphere_file.h"
#include "models/scene_file.h"
#include "models/weights_file.h"

#define MAX_INPUTS 16

typedef struct codegen_options {
  const char *weights[MAX_INPUTS];
  int n_weights;
  const char *atmosphere_path, *scene_path, *baselines, *out_dir, *name, *prefix;
  int naive_steps, naive_steps_given, want_c, want_glsl, quiet;
} codegen_options;

static void codegen_usage(FILE *out) {
  fprintf(out,
          "usage: skyfit codegen [--weights W.json ...]\n"
          "                      [--baselines naive,chapman,taylor,flat,spline,naive-sky,raymarched-sky,\n"
          "                                   flat-sky,schuler-sky]\n"
          "                      --lang glsl|c|both --out DIR [options]\n"
          "\n"
          "Writes DIR/NAME.h (C99/C++) and/or DIR/NAME.glsl holding, for every model asked\n"
          "for, functions skyfit_<model>_<quantity>(...) with the same names and signatures\n"
          "in both languages, its constants, and a header comment naming the atmosphere,\n"
          "its hash, the domain and the measured error. Only what is asked is emitted.\n"
          "\n"
          "options:\n"
          "  --weights FILE     a fitted model's weights file (SPEC §8); repeatable\n"
          "  --baselines LIST   analytic baselines (SPEC §7.6), comma-separated. Transmittance:\n"
          "                     naive (N-step midpoint raymarch of the densities),\n"
          "                     chapman (Schuler, seed 000 eq. 22-25), taylor (Galaj, seed 002\n"
          "                     eq. 17), flat (Leenman's flat/DR-1 model, seed 000 eq. 51, 53,\n"
          "                     59), spline (Galaj, seed 002 IV.E: Hermite meshes 50 x 20 as\n"
          "                     constant arrays); all but naive need an exponential\n"
          "                     constituent. Sky radiance (single scattering): naive-sky\n"
          "                     (16 view x 8 sun steps, seed 000 11.2.6:\n"
          "                     skyfit_naive_sky_radiance) and raymarched-sky (Leenman's\n"
          "                     raymarched model, seed 000 11.2.10: 5 steps integrated in\n"
          "                     closed form with the flat model's optical depths:\n"
          "                     skyfit_raymarched_sky_radiance; at most 4 constituents) and\n"
          "                     flat-sky (Leenman's flat model, seed 000 11.2.9: the same in one\n"
          "                     step, eq. 52 and 55: skyfit_flat_sky_radiance) and schuler-sky\n"
          "                     (seed 000 11.2.7: 24 view steps, the sun's depths by the Chapman\n"
          "                     approximation: skyfit_schuler_sky_radiance; at most 4\n"
          "                     constituents, at least one exponential).\n"
          "                     Every baseline: at most 4 channels\n"
          "  --naive-steps N    raymarch steps of the naive baseline (default %d)\n"
          "  --atmosphere FILE  atmosphere of the baselines (default: the scene's, else the\n"
          "                     built-in Earth)\n"
          "  --scene FILE       scene: the baselines' atmosphere and the domain their error\n"
          "                     is measured on (default: the built-in scene)\n"
          "  --lang L           glsl, c, both or glsl,c (required)\n"
          "  --out DIR          output folder (required; must exist)\n"
          "  --name NAME        file name without extension (default skyfit)\n"
          "  --prefix P         begin every emitted name with P_ instead of skyfit_ (types and\n"
          "                     macros too, P_ upper-cased): two scenes' headers in one program\n"
          "  --quiet            no summary on stderr\n"
          "  --help             this text\n",
          SF_BASELINE_DEFAULT_STEPS);
}

static int parse_lang(const char *s, codegen_options *o) {
  if (strcmp(s, "glsl") == 0) o->want_glsl = 1;
  else if (strcmp(s, "c") == 0) o->want_c = 1;
  else if (strcmp(s, "both") == 0 || strcmp(s, "glsl,c") == 0 || strcmp(s, "c,glsl") == 0)
    o->want_c = o->want_glsl = 1;
  else return -1;
  return 0;
}

/* Whether the --baselines list (NULL: none) names the naive raymarch. */
static int lists_naive(const char *baselines) {
  for (const char *p = baselines; p && *p;) {
    size_t n = strcspn(p, ",");
    if (n == 5 && strncmp(p, "naive", 5) == 0) return 1;
    p += n + (p[n] == ',');
  }
  return 0;
}

static int parse_options(int argc, char **argv, codegen_options *o) {
  memset(o, 0, sizeof *o);
  o->naive_steps = SF_BASELINE_DEFAULT_STEPS;
  o->name = "skyfit";
  for (int i = 1; i < argc; ++i) {
    const char *a = argv[i];
    const char *next = sf_cli_value_after(argc, argv, i);
    int takes = strcmp(a, "--weights") == 0 || strcmp(a, "--atmosphere") == 0 ||
                strcmp(a, "--scene") == 0 || strcmp(a, "--baselines") == 0 ||
                strcmp(a, "--naive-steps") == 0 || strcmp(a, "--lang") == 0 ||
                strcmp(a, "--out") == 0 || strcmp(a, "--name") == 0 || strcmp(a, "--prefix") == 0;
    if (strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0) return 1;
    if (strcmp(a, "--quiet") == 0) {
      o->quiet = 1;
      continue;
    }
    if (!takes) {
      fprintf(stderr, "skyfit codegen: unknown option '%s' (see --help)\n", a);
      return 2;
    }
    if (!next) {
      sf_cli_bad_option("skyfit codegen", a, a);
      return 2;
    }
    ++i;
    if (strcmp(a, "--weights") == 0) {
      if (o->n_weights == MAX_INPUTS) {
        fprintf(stderr, "skyfit codegen: at most %d weights files\n", MAX_INPUTS);
        return 2;
      }
      o->weights[o->n_weights++] = next;
    } else if (strcmp(a, "--atmosphere") == 0) o->atmosphere_path = next;
    else if (strcmp(a, "--scene") == 0) o->scene_path = next;
    else if (strcmp(a, "--baselines") == 0) o->baselines = next;
    else if (strcmp(a, "--out") == 0) o->out_dir = next;
    else if (strcmp(a, "--name") == 0) o->name = next;
    else if (strcmp(a, "--prefix") == 0) {
      sf_error perr = {0};
      if (sf_codegen_prefix_check(next, &perr) != SF_OK) {
        fprintf(stderr, "skyfit codegen: --prefix: %s\n", perr.message);
        return 2;
      }
      o->prefix = next;
    }
    else if (strcmp(a, "--naive-steps") == 0) {
      char *end;
      long n = strtol(next, &end, 10);
      if (*end || n < 1 || n > 4096) {
        fprintf(stderr, "skyfit codegen: --naive-steps: expected 1..4096, got '%s'\n", next);
        return 2;
      }
      o->naive_steps = (int)n;
      o->naive_steps_given = 1;
    } else if (parse_lang(next, o) != 0) {
      fprintf(stderr, "skyfit codegen: --lang: expected glsl, c or both, got '%s'\n", next);
      return 2;
    }
  }
  if (!o->want_c && !o->want_glsl) {
    fprintf(stderr, "skyfit codegen: --lang is required (glsl, c or both)\n");
    return 2;
  }
  if (!o->out_dir) {
    fprintf(stderr, "skyfit codegen: --out DIR is required\n");
    return 2;
  }
  if (!o->n_weights && !o->baselines) {
    fprintf(stderr, "skyfit codegen: nothing to emit: give --weights and/or --baselines\n");
    return 2;
  }
  /* Every item named: strtok below skips empty ones, and `--baselines ""`
   * had replaced the headers with empty ones, exit 0. */
  if (o->baselines) {
    size_t len = strlen(o->baselines);
    const char *b = o->baselines;
    if (len == 0 || b[0] == ',' || b[len - 1] == ',' || strstr(b, ",,")) {
      fprintf(stderr, "skyfit codegen: --baselines: '%s' has an empty item: give names separated by single commas\n",
              b);
      return 2;
    }
    if (len >= 256) {
      fprintf(stderr, "skyfit codegen: --baselines: the list is %zu characters long (at most 255)\n", len);
      return 2;
    }
  }
  /* as skyfit sample and fit: one source of the atmosphere */
  if (o->atmosphere_path && o->scene_path) {
    fprintf(stderr, "skyfit codegen: --atmosphere and --scene both name the atmosphere: give one\n");
    return 2;
  }
  /* it had been accepted and ignored without the naive baseline */
  if (o->naive_steps_given && !lists_naive(o->baselines)) {
    fprintf(stderr, "skyfit codegen: --naive-steps applies to the naive baseline (--baselines naive,...)\n");
    return 2;
  }
  /* a weights file carries its own atmosphere */
  if ((o->atmosphere_path || o->scene_path) && !o->baselines) {
    fprintf(stderr, "skyfit codegen: --atmosphere and --scene apply to --baselines (a weights file holds its "
                    "own atmosphere)\n");
    return 2;
  }
  for (const char *c = o->name; *c; ++c)
    if (!((*c >= 'a' && *c <= 'z') || (*c >= 'A' && *c <= 'Z') || (*c >= '0' && *c <= '9') ||
          *c == '_' || *c == '-')) {
      fprintf(stderr, "skyfit codegen: --name: letters, digits, '_' and '-' only, got '%s'\n",
              o->name);
      return 2;
    }
  /* A header may not be one of the inputs: a header path that is a link
   * to a --weights file had replaced the weights with the header (outputs
   * follow links, util/atomic_file.h). */
  const char *inputs[MAX_INPUTS + 2];
  int n_inputs = 0;
  for (int i = 0; i < o->n_weights; ++i) inputs[n_inputs++] = o->weights[i];
  inputs[n_inputs++] = o->atmosphere_path;
  inputs[n_inputs++] = o->scene_path;
  for (int k = 0; k < 2; ++k) {
    if (!(k ? o->want_glsl : o->want_c)) continue;
    char header[4200];
    snprintf(header, sizeof header, "%s/%s.%s", o->out_dir, o->name, k ? "glsl" : "h");
    const char *clash = sf_cli_same_as_any(header, inputs, n_inputs);
    if (clash) {
      fprintf(stderr, "skyfit codegen: %s is the same file as the input %s; give another --out or --name\n", header,
              clash);
      return 2;
    }
  }
  return 0;
}

typedef struct codegen_job {
  sf_scene scene;                  /* large: heap */
  sf_scene_domain domain;
  sf_baseline baselines[SF_BASELINE_COUNT];
  int n_baselines;
  sf_spline_model spline;          /* the spline baseline's meshes, if asked */
  sf_sky_naive sky[2];             /* --baselines naive-sky, schuler-sky */
  int has_sky[2];
  sf_sky_raymarched raymarched[2];   /* --baselines raymarched-sky, flat-sky */
  int has_raymarched[2];
  sf_weights weights[MAX_INPUTS];
  sf_fitted_model *fitted[MAX_INPUTS];
  int n_weights;
  sf_codegen_part parts[MAX_INPUTS + SF_BASELINE_COUNT + 4];
  int n_parts;
} codegen_job;

static int load_scene(const codegen_options *o, codegen_job *job, sf_error *err) {
  if (o->scene_path) {
    if (sf_scene_load_file(o->scene_path, &job->scene, err) != SF_OK) return err->status;
  } else {
    sf_scene_default(&job->scene);
  }
  if (o->atmosphere_path &&
      sf_atmosphere_load_file(o->atmosphere_path, &job->scene.atmosphere, err) != SF_OK)
    return err->status;
  sf_cli_warn_atmosphere_units("skyfit codegen", o->atmosphere_path ? o->atmosphere_path : job->scene.atmosphere_path,
                               &job->scene.atmosphere);
  return sf_scene_get_domain(&job->scene, &job->domain, err);
}

static int add_baselines(const codegen_options *o, codegen_job *job, sf_error *err) {
  char list[256];
  snprintf(list, sizeof list, "%s", o->baselines);
  for (char *save = NULL, *item = strtok_r(list, ",", &save); item;
       item = strtok_r(NULL, ",", &save)) {
    int schuler = strcmp(item, "schuler-sky") == 0;
    if (schuler || strcmp(item, "naive-sky") == 0) {   /* models/sky_naive.h */
      if (job->has_sky[schuler]) return sf_fail(err, SF_ERR_INPUT, "--baselines: '%s' given twice", item);
      if (schuler) sf_sky_schuler_make(&job->scene.atmosphere, &job->sky[1]);
      else job->sky[0] = (sf_sky_naive){.atm = &job->scene.atmosphere, .view_steps = SF_SKY_NAIVE_VIEW_STEPS,
                                         .sun_steps = SF_SKY_NAIVE_SUN_STEPS};
      job->has_sky[schuler] = 1;
      if (sf_sky_naive_part(&job->sky[schuler], &job->domain, &job->parts[job->n_parts], err) != SF_OK)
        return err->status;
      ++job->n_parts;
      continue;
    }
    int flat = strcmp(item, "flat-sky") == 0;
    if (flat || strcmp(item, "raymarched-sky") == 0) {   /* Leenman's (models/sky_raymarched.h) */
      if (job->has_raymarched[flat]) return sf_fail(err, SF_ERR_INPUT, "--baselines: '%s' given twice", item);
      sf_sky_raymarched_make(&job->scene.atmosphere, flat ? SF_SKY_FLAT_STEPS : SF_SKY_RAYMARCHED_STEPS,
                             SF_RAYMARCHED_DEPTHS_FLAT, &job->raymarched[flat]);
      job->has_raymarched[flat] = 1;
      if (sf_sky_raymarched_part(&job->raymarched[flat], flat, &job->domain, &job->parts[job->n_parts], err) !=
          SF_OK)
        return err->status;
      ++job->n_parts;
      continue;
    }
    int kind = sf_baseline_kind_parse(item);
    if (kind < 0)
      return sf_fail(err, SF_ERR_INPUT,
                     "--baselines: unknown baseline '%s' (expected naive, chapman, taylor, flat, spline, naive-sky, "
                     "raymarched-sky, flat-sky, schuler-sky)",
                     item);
    for (int k = 0; k < job->n_baselines; ++k)
      if ((int)job->baselines[k].kind == kind)
        return sf_fail(err, SF_ERR_INPUT, "--baselines: '%s' given twice", item);
    sf_baseline *b = &job->baselines[job->n_baselines++];
    b->kind = (sf_baseline_kind)kind;
    b->steps = o->naive_steps;
    b->atmosphere = &job->scene.atmosphere;
    if (b->kind == SF_BASELINE_SPLINE) {
      if (sf_spline_model_make(b->atmosphere, SF_SPLINE_HEIGHT_POINTS, SF_SPLINE_DISTANCE_POINTS,
                               &job->spline) != 0)
        return sf_fail(err, SF_ERR_INTERNAL, "--baselines spline: out of memory");
      b->spline = &job->spline;
    }
    if (sf_baseline_part(b, &job->domain, &job->parts[job->n_parts], err) != SF_OK)
      return err->status;
    ++job->n_parts;
  }
  return SF_OK;
}

static int run(const codegen_options *o, codegen_job *job, sf_error *err) {
  if (o->baselines) {
    if (load_scene(o, job, err) != SF_OK) return err->status;
    if (add_baselines(o, job, err) != SF_OK) return err->status;
  }
  int first_weights_part = job->n_parts;
  for (int i = 0; i < o->n_weights; ++i) {
    if (sf_weights_load_file(o->weights[i], NULL, &job->weights[i], err) != SF_OK)
      return err->status;
    job->n_weights = i + 1;
    if (sf_fitted_part(&job->weights[i], &job->fitted[i], &job->parts[job->n_parts], err) != SF_OK)
      return err->status;
    ++job->n_parts;
  }
  sf_fitted_link(job->fitted, job->parts + first_weights_part, job->n_weights);
  return sf_codegen_write(job->parts, job->n_parts, o->want_c, o->want_glsl, o->out_dir, o->name, o->prefix,
                          err);
}

int sf_cmd_codegen(int argc, char **argv) {
  codegen_options o;
  int parsed = parse_options(argc, argv, &o);
  if (parsed == 1) {
    codegen_usage(stdout);
    return 0;
  }
  if (parsed != 0) return parsed;
  codegen_job *job = calloc(1, sizeof *job);
  if (!job) {
    fprintf(stderr, "skyfit codegen: out of memory\n");
    return 1;
  }
  sf_error err;
  sf_error_clear(&err);
  /* a signal leaves no header's temporary (cli/interrupt_cleanup.h) */
  sf_cli_outputs outputs = {0};
  sf_cli_outputs_add_folder(&outputs, o.out_dir);
  sf_cli_supervise_outputs(&outputs);
  int status = run(&o, job, &err);
  if (status != SF_OK) fprintf(stderr, "skyfit codegen: %s\n", err.message);
  else if (!o.quiet) {
    for (int p = 0; p < job->n_parts; ++p)
      fprintf(stderr, "skyfit codegen: %s %s -> %s/%s%s%s\n", job->parts[p].name,
              job->parts[p].quantity, o.out_dir, o.name,
              o.want_c ? ".h" : "", o.want_glsl ? (o.want_c ? " .glsl" : ".glsl") : "");
    /* eq. 44 takes the transmittance network's values: without one the
     * segment function is left out, which a renderer would otherwise find
     * only when its call does not compile */
    for (int i = 0; i < job->n_weights; ++i)
      if (job->fitted[i] && job->fitted[i]->kind == SF_FITTED_MLP_SCATTERING && !job->fitted[i]->transmittance)
        fprintf(stderr, "skyfit codegen: %s: no transmittance network of its atmosphere among --weights, so "
                "skyfit_mlp_sky_radiance_segment (eq. 44) is not emitted\n", job->weights[i].source);
  }
  for (int i = 0; i < job->n_weights; ++i) {
    sf_fitted_free(job->fitted[i]);
    sf_weights_free(&job->weights[i]);
  }
  sf_spline_model_free(&job->spline);
  free(job);
  return status;
}
