/* The weights file (SPEC §8): one JSON file per fitted model, holding what
 * the model is, the atmosphere it was fitted for (full JSON and its hash),
 * the domain it is valid on, its input normalisation, its parameters, the
 * measured metrics and how it was trained:
 *
 *   {"skyfit_weights": 1, "model": "hosek", "quantity": "sky_radiance",
 *    "atmosphere": {...canonical atmosphere...}, "atmosphere_hash": "0123...",
 *    "domain": {"h_km": [0, 0], "mu": [0, 1], "mu_s": [0, 1]},
 *    "inputs": [{"name": "h_km", "offset": 0, "scale": 0.01}, ...],
 *    "params": {"A": [[...], ...], "scale": [...], ...},
 *    "metrics": {"rmse": 1e-3, "max_abs": ..., ...},
 *    "training": {"seed": 1, "epochs": 200, "loss": "mse"}}
 *
 * Every fit skyfit writes gives "training" a "seed" and "epochs": those of
 * the networks; for the deterministic fits seed 0, and the passes over the
 * data, Levenberg-Marquardt iterations or Nelder-Mead evaluations
 * (fit/fit_weights_doc.c, fit/spectral4_run.h).
 *
 * "params" maps a name to a number or a rectangular nested array of numbers
 * (at most SF_WEIGHTS_MAX_DIMS deep); "inputs" and "training" may be
 * omitted; "metrics" holds numbers, strings, or objects/arrays of them.
 * Everything numeric must be finite. The model-specific meaning of the
 * params (names, shapes) is checked by the model's own loader through
 * sf_weights_param, which names the file and key path on a mismatch.
 *
 * Errors are SF_ERR_INPUT with "<file>: <key path>: <problem>". */
#ifndef SKYFIT_MODELS_WEIGHTS_FILE_H
#define SKYFIT_MODELS_WEIGHTS_FILE_H

#include <cjson/cJSON.h>

#include "models/atmosphere.h"
#include "models/scene_file.h"
#include "util/error.h"

#define SF_WEIGHTS_FORMAT_VERSION 1
#define SF_WEIGHTS_MAX_DIMS 4
#define SF_WEIGHTS_MAX_BYTES ((size_t)64 << 20)
#define SF_WEIGHTS_NAME_LEN 64

/* One entry of "inputs": normalised = (value - offset) * scale. */
typedef struct sf_weights_input {
  char name[SF_WEIGHTS_NAME_LEN];
  double offset, scale;
} sf_weights_input;

#define SF_WEIGHTS_MAX_INPUTS 16

/* A loaded, validated weights file. Owns root (free with sf_weights_free). */
typedef struct sf_weights {
  char source[512];                      /* file name, for messages */
  char model[SF_WEIGHTS_NAME_LEN];       /* "sigmoid", "hosek", "mlp-scattering", ... */
  char quantity[SF_WEIGHTS_NAME_LEN];    /* "transmittance", "sky_radiance", ... */
  sf_atmosphere atmosphere;
  char atmosphere_hash[17];
  sf_scene_domain domain;
  int n_inputs;
  sf_weights_input inputs[SF_WEIGHTS_MAX_INPUTS];
  cJSON *root;     /* the whole document; params/metrics/training read from it */
  /* params_read[i]: whether sf_weights_param has read the i-th entry of
   * params (file order), n_params of them; owned. Bookkeeping for
   * sf_weights_check_params_read, the one thing reading a param changes. */
  unsigned char *params_read;
  int n_params;
} sf_weights;

/* For a model whose inputs are not learnt (sigmoid, Perez, Hosek): the
 * file's "inputs" must be exactly these n (names, offsets and scales, as
 * its writer writes them), or be absent; SF_ERR_INPUT naming the file and
 * the key otherwise (a file that declared another normalisation had been
 * read as if it declared this one). */
int sf_weights_check_fixed_inputs(const sf_weights *w, const sf_weights_input *expected, int n, sf_error *err);

/* ---- writing ---- */

/* A new document with the header keys filled in (model, quantity, the
 * atmosphere's canonical JSON and hash, the domain). NULL when out of
 * memory. The caller adds inputs/params/metrics/training and writes it. */
cJSON *sf_weights_new(const char *model, const char *quantity, const sf_atmosphere *atm,
                      const sf_scene_domain *domain);

/* Adds one "inputs" entry (creating the array on first use). */
int sf_weights_add_input(cJSON *doc, const char *name, double offset, double scale);

/* Adds params[name] = values, a row-major array of the given shape
 * (n_dims 0: a single number). */
int sf_weights_add_param(cJSON *doc, const char *name, int n_dims, const int *shape,
                         const double *values);

/* The object "metrics" / "training" (created on first use), to which the
 * caller adds members with cJSON_AddNumberToObject etc. */
cJSON *sf_weights_metrics(cJSON *doc);
cJSON *sf_weights_training(cJSON *doc);

/* Prints the document (keys in insertion order, numbers round-trip exact)
 * and writes it atomically (temp + rename). Nothing is written on failure. */
int sf_weights_write(const cJSON *doc, const char *path, sf_error *err);
/* The printed text (malloc'd; caller frees), as written by sf_weights_write. */
char *sf_weights_print(const cJSON *doc);

/* ---- reading ---- */

/* Parses and validates a weights file (see above). expected_model: NULL
 * accepts any model; otherwise a different "model" is an error. The
 * atmosphere is loaded with the atmosphere file's validation and its hash
 * must equal "atmosphere_hash". On failure *out is empty (safe to free). */
int sf_weights_load_file(const char *path, const char *expected_model, sf_weights *out,
                         sf_error *err);
int sf_weights_load_string(const char *json, const char *source_name, const char *expected_model,
                           sf_weights *out, sf_error *err);
void sf_weights_free(sf_weights *w);

/* Reads params[name] into values (capacity n_values) and checks its shape:
 * n_dims and shape[] as expected (shape[k] = -1 accepts any size on that
 * axis and stores the size found). Missing, wrong shape, too many values:
 * SF_ERR_INPUT "<file>: params.<name>: expected an array of shape 4x3, got 4x2". */
int sf_weights_param(const sf_weights *w, const char *name, int n_dims, int *shape,
                     double *values, int n_values, sf_error *err);

/* SF_OK when every entry of params has been read by sf_weights_param;
 * else SF_ERR_INPUT naming the file and the first entry left unread: a
 * model's loader calls it once it has read all it takes, so that a
 * misspelt or foreign parameter ("norm_capp", a ground network in a
 * transmittance file) is refused rather than silently ignored. */
int sf_weights_check_params_read(const sf_weights *w, sf_error *err);

/* metrics[name] as a number, or NAN when absent or not a number. */
double sf_weights_metric(const sf_weights *w, const char *name);

/* JSON text of the domain in the form above ({"h_km": [...], ...}). */
cJSON *sf_weights_domain_json(const sf_scene_domain *d);

#endif
