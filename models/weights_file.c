/* The weights file (SPEC §8): writing and validated reading. */
#include "models/weights_file.h"

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "models/atmosphere_file.h"
#include "util/json_read.h"
#include "util/json_exact.h"

/* ---------------------------------------------------------------- writing */

cJSON *sf_weights_domain_json(const sf_scene_domain *d) {
  cJSON *o = cJSON_CreateObject();
  if (!o) return NULL;
  const double pairs[3][2] = {{d->h_min_km, d->h_max_km}, {d->mu_min, d->mu_max}, {d->mu_s_min, d->mu_s_max}};
  static const char *const names[3] = {"h_km", "mu", "mu_s"};
  for (int i = 0; i < 3; ++i) {
    cJSON *a = cJSON_CreateDoubleArray(pairs[i], 2);
    if (!a || !cJSON_AddItemToObject(o, names[i], a)) {
      cJSON_Delete(a);
      cJSON_Delete(o);
      return NULL;
    }
  }
  return o;
}

cJSON *sf_weights_new(const char *model, const char *quantity, const sf_atmosphere *atm,
                      const sf_scene_domain *domain) {
  cJSON *doc = cJSON_CreateObject();
  char *atm_json = sf_atmosphere_to_json(atm);
  cJSON *atm_tree = atm_json ? cJSON_Parse(atm_json) : NULL;
  free(atm_json);
  cJSON *dom = sf_weights_domain_json(domain);
  char hash[17];
  sf_atmosphere_hash_hex(atm, hash);
  if (!doc || !atm_tree || !dom || !cJSON_AddNumberToObject(doc, "skyfit_weights", SF_WEIGHTS_FORMAT_VERSION) ||
      !cJSON_AddStringToObject(doc, "model", model) || !cJSON_AddStringToObject(doc, "quantity", quantity) ||
      !cJSON_AddItemToObject(doc, "atmosphere", atm_tree)) {
    cJSON_Delete(doc);
    cJSON_Delete(atm_tree);
    cJSON_Delete(dom);
    return NULL;
  }
  if (!cJSON_AddStringToObject(doc, "atmosphere_hash", hash) || !cJSON_AddItemToObject(doc, "domain", dom)) {
    cJSON_Delete(doc);
    cJSON_Delete(dom);
    return NULL;
  }
  return doc;
}

int sf_weights_add_input(cJSON *doc, const char *name, double offset, double scale) {
  if (!isfinite(offset) || !isfinite(scale)) return SF_ERR_INTERNAL;
  cJSON *inputs = cJSON_GetObjectItemCaseSensitive(doc, "inputs");
  if (!inputs) inputs = cJSON_AddArrayToObject(doc, "inputs");
  cJSON *entry = cJSON_CreateObject();
  if (!inputs || !entry || !cJSON_AddStringToObject(entry, "name", name) ||
      !cJSON_AddNumberToObject(entry, "offset", offset) || !cJSON_AddNumberToObject(entry, "scale", scale) ||
      !cJSON_AddItemToArray(inputs, entry)) {
    cJSON_Delete(entry);
    return SF_ERR_INTERNAL;
  }
  return SF_OK;
}

/* Nested arrays for dims [dim, n_dims) of a row-major block. */
static cJSON *nested_array(int n_dims, const int *shape, const double *values) {
  if (n_dims == 0) return cJSON_CreateNumber(values[0]);
  if (n_dims == 1) return cJSON_CreateDoubleArray(values, shape[0]);
  size_t stride = 1;
  for (int k = 1; k < n_dims; ++k) stride *= (size_t)shape[k];
  cJSON *a = cJSON_CreateArray();
  for (int i = 0; a && i < shape[0]; ++i) {
    cJSON *row = nested_array(n_dims - 1, shape + 1, values + (size_t)i * stride);
    if (!row || !cJSON_AddItemToArray(a, row)) {
      cJSON_Delete(row);
      cJSON_Delete(a);
      return NULL;
    }
  }
  return a;
}

int sf_weights_add_param(cJSON *doc, const char *name, int n_dims, const int *shape,
                         const double *values) {
  if (n_dims < 0 || n_dims > SF_WEIGHTS_MAX_DIMS) return SF_ERR_INTERNAL;
  size_t n = 1;
  for (int k = 0; k < n_dims; ++k) {
    if (shape[k] < 1) return SF_ERR_INTERNAL;
    n *= (size_t)shape[k];
  }
  for (size_t i = 0; i < n; ++i)
    if (!isfinite(values[i])) return SF_ERR_INTERNAL;
  cJSON *params = cJSON_GetObjectItemCaseSensitive(doc, "params");
  if (!params) params = cJSON_AddObjectToObject(doc, "params");
  cJSON *v = params ? nested_array(n_dims, shape, values) : NULL;
  if (!v || !cJSON_AddItemToObject(params, name, v)) {
    cJSON_Delete(v);
    return SF_ERR_INTERNAL;
  }
  return SF_OK;
}

static cJSON *object_member(cJSON *doc, const char *name) {
  cJSON *o = cJSON_GetObjectItemCaseSensitive(doc, name);
  return o ? o : cJSON_AddObjectToObject(doc, name);
}
cJSON *sf_weights_metrics(cJSON *doc) { return object_member(doc, "metrics"); }
cJSON *sf_weights_training(cJSON *doc) { return object_member(doc, "training"); }

/* 1 if every number in the tree is finite (cJSON would print NaN as null). */
static int all_finite(const cJSON *node) {
  if (cJSON_IsNumber(node)) return isfinite(node->valuedouble);
  for (const cJSON *c = node->child; c; c = c->next)
    if (!all_finite(c)) return 0;
  return 1;
}

char *sf_weights_print(const cJSON *doc) {
  char *text = sf_json_print_exact(doc, 1);
  if (!text) return NULL;
  size_t n = strlen(text);
  char *with_newline = realloc(text, n + 2);
  if (!with_newline) {
    free(text);
    return NULL;
  }
  with_newline[n] = '\n';
  with_newline[n + 1] = '\0';
  return with_newline;
}

int sf_weights_write(const cJSON *doc, const char *path, sf_error *err) {
  if (!all_finite(doc))
    return sf_fail(err, SF_ERR_INTERNAL, "%s: refusing to write a weights file with a non-finite number", path);
  return sf_json_write_exact(doc, path, err);
}

/* ---------------------------------------------------------------- reading */

static const char *const top_keys[] = {"skyfit_weights", "model", "quantity", "atmosphere", "atmosphere_hash",
                                       "domain", "inputs", "params", "metrics", "training", NULL};

static int read_name(const sf_json_ctx *c, const cJSON *root, const char *key, char *out, size_t n) {
  const cJSON *v = sf_json_get(root, key);
  if (!v) return sf_json_fail(c, key, "missing");
  if (!cJSON_IsString(v)) return sf_json_fail(c, key, "expected a string, got %s", sf_json_type_name(v));
  if (!v->valuestring[0] || strlen(v->valuestring) >= n)
    return sf_json_fail(c, key, "must be 1 to %zu characters", n - 1);
  snprintf(out, n, "%s", v->valuestring);
  return SF_OK;
}

static int read_range(const sf_json_ctx *c, const cJSON *dom, const char *key, double lim_lo, double lim_hi,
                      double *lo, double *hi) {
  char path[SF_JSON_PATH_LEN];
  sf_json_join_key(path, sizeof path, "domain", key);
  const cJSON *v = sf_json_get(dom, key);
  if (!v) return sf_json_fail(c, path, "missing");
  if (!cJSON_IsArray(v) || cJSON_GetArraySize(v) != 2)
    return sf_json_fail(c, path, "expected [min, max], got %s", sf_json_type_name(v));
  double r[2];
  for (int i = 0; i < 2; ++i) {
    char epath[SF_JSON_PATH_LEN];
    sf_json_join_index(epath, sizeof epath, path, i);
    if (sf_json_read_finite(c, cJSON_GetArrayItem(v, i), epath, &r[i])) return SF_ERR_INPUT;
  }
  if (r[0] > r[1]) return sf_json_fail(c, path, "min %.17g exceeds max %.17g", r[0], r[1]);
  if (r[0] < lim_lo || r[1] > lim_hi)
    return sf_json_fail(c, path, "must lie within [%g, %g], got [%.17g, %.17g]", lim_lo, lim_hi, r[0], r[1]);
  *lo = r[0];
  *hi = r[1];
  return SF_OK;
}

static int read_domain(const sf_json_ctx *c, const cJSON *root, sf_scene_domain *d) {
  const cJSON *dom = sf_json_get(root, "domain");
  if (!dom) return sf_json_fail(c, "domain", "missing");
  if (!cJSON_IsObject(dom)) return sf_json_fail(c, "domain", "expected an object, got %s", sf_json_type_name(dom));
  static const char *const keys[] = {"h_km", "mu", "mu_s", NULL};
  if (sf_json_check_keys(c, dom, "domain", keys)) return SF_ERR_INPUT;
  if (read_range(c, dom, "h_km", 0.0, INFINITY, &d->h_min_km, &d->h_max_km) ||
      read_range(c, dom, "mu", -1.0, 1.0, &d->mu_min, &d->mu_max) ||
      read_range(c, dom, "mu_s", -1.0, 1.0, &d->mu_s_min, &d->mu_s_max))
    return SF_ERR_INPUT;
  return SF_OK;
}

/* SF_OK when x, a number the emitted code holds as float32, does not round
 * beyond FLT_MAX; else the failure at path. */
static int within_float32(const sf_json_ctx *c, const char *path, double x) {
  if (!isinf((float)x)) return SF_OK;
  return sf_json_fail(c, path, "%.17g is beyond float32's range (%.9g), which the emitted code holds", x,
                      (double)FLT_MAX);
}

static int read_inputs(const sf_json_ctx *c, const cJSON *root, sf_weights *w) {
  const cJSON *v = sf_json_get(root, "inputs");
  if (!v) return SF_OK;
  if (!cJSON_IsArray(v)) return sf_json_fail(c, "inputs", "expected an array, got %s", sf_json_type_name(v));
  int n = cJSON_GetArraySize(v);
  if (n > SF_WEIGHTS_MAX_INPUTS) return sf_json_fail(c, "inputs", "too many entries (%d, at most %d)", n, SF_WEIGHTS_MAX_INPUTS);
  static const char *const keys[] = {"name", "offset", "scale", NULL};
  for (int i = 0; i < n; ++i) {
    char path[SF_JSON_PATH_LEN], kpath[SF_JSON_PATH_LEN];
    sf_json_join_index(path, sizeof path, "inputs", i);
    const cJSON *e = cJSON_GetArrayItem(v, i);
    if (!cJSON_IsObject(e)) return sf_json_fail(c, path, "expected an object, got %s", sf_json_type_name(e));
    if (sf_json_check_keys(c, e, path, keys)) return SF_ERR_INPUT;
    sf_weights_input *in = &w->inputs[i];
    const cJSON *name = sf_json_get(e, "name");
    sf_json_join_key(kpath, sizeof kpath, path, "name");
    if (!cJSON_IsString(name) || !name->valuestring[0] || strlen(name->valuestring) >= sizeof in->name)
      return sf_json_fail(c, kpath, "expected a non-empty string");
    snprintf(in->name, sizeof in->name, "%s", name->valuestring);
    sf_json_join_key(kpath, sizeof kpath, path, "offset");
    const cJSON *off = sf_json_get(e, "offset");
    if (!off) return sf_json_fail(c, kpath, "missing");
    /* as params (array_shape below): an offset of 1e300 had stopped codegen
     * with "constant inf is not a finite float32", naming no file nor key */
    if (sf_json_read_finite(c, off, kpath, &in->offset) || within_float32(c, kpath, in->offset))
      return SF_ERR_INPUT;
    sf_json_join_key(kpath, sizeof kpath, path, "scale");
    const cJSON *sc = sf_json_get(e, "scale");
    if (!sc) return sf_json_fail(c, kpath, "missing");
    if (sf_json_read_finite(c, sc, kpath, &in->scale)) return SF_ERR_INPUT;
    if (in->scale == 0.0) return sf_json_fail(c, kpath, "must not be 0");
    if (within_float32(c, kpath, in->scale)) return SF_ERR_INPUT;
  }
  w->n_inputs = n;
  return SF_OK;
}

/* Shape of a number or rectangular nested array of finite numbers within
 * float32's range: the emitted code holds them as float32 (SPEC §8), and a
 * weight of 1e300 had loaded, evaluated and passed `fit sigmoid --check`,
 * then stopped `skyfit codegen` with a message naming no file nor key. */
static int array_shape(const sf_json_ctx *c, const cJSON *v, const char *path, int depth, int *n_dims,
                       int *shape) {
  if (cJSON_IsNumber(v)) {
    double x;
    if (sf_json_read_finite(c, v, path, &x) || within_float32(c, path, x)) return SF_ERR_INPUT;
    *n_dims = 0;
    return SF_OK;
  }
  if (!cJSON_IsArray(v))
    return sf_json_fail(c, path, "expected a number or an array of numbers, got %s", sf_json_type_name(v));
  if (depth >= SF_WEIGHTS_MAX_DIMS) return sf_json_fail(c, path, "nested deeper than %d", SF_WEIGHTS_MAX_DIMS);
  int n = cJSON_GetArraySize(v);
  if (n < 1) return sf_json_fail(c, path, "empty array");
  int first_dims = -1, first_shape[SF_WEIGHTS_MAX_DIMS];
  for (int i = 0; i < n; ++i) {
    char epath[SF_JSON_PATH_LEN];
    sf_json_join_index(epath, sizeof epath, path, i);
    int dims, sub[SF_WEIGHTS_MAX_DIMS];
    if (array_shape(c, cJSON_GetArrayItem(v, i), epath, depth + 1, &dims, sub)) return SF_ERR_INPUT;
    if (i == 0) {
      first_dims = dims;
      memcpy(first_shape, sub, sizeof sub);
    } else if (dims != first_dims || memcmp(sub, first_shape, (size_t)dims * sizeof(int)) != 0) {
      return sf_json_fail(c, epath, "rows differ in shape (the array must be rectangular)");
    }
  }
  *n_dims = first_dims + 1;
  shape[0] = n;
  memcpy(shape + 1, first_shape, (size_t)first_dims * sizeof(int));
  return SF_OK;
}

static int read_params(const sf_json_ctx *c, const cJSON *root) {
  const cJSON *p = sf_json_get(root, "params");
  if (!p) return sf_json_fail(c, "params", "missing");
  if (!cJSON_IsObject(p)) return sf_json_fail(c, "params", "expected an object, got %s", sf_json_type_name(p));
  if (sf_json_check_duplicate_keys(c, p, "params")) return SF_ERR_INPUT;
  for (const cJSON *e = p->child; e; e = e->next) {
    char path[SF_JSON_PATH_LEN];
    sf_json_join_key(path, sizeof path, "params", e->string);
    int dims, shape[SF_WEIGHTS_MAX_DIMS];
    if (array_shape(c, e, path, 0, &dims, shape)) return SF_ERR_INPUT;
  }
  return SF_OK;
}

/* Metrics and training: numbers (finite), strings, booleans, null-free
 * objects and arrays of them. */
static int check_plain_values(const sf_json_ctx *c, const cJSON *v, const char *path) {
  if (cJSON_IsNumber(v)) {
    double x;
    return sf_json_read_finite(c, v, path, &x);
  }
  if (cJSON_IsString(v) || cJSON_IsBool(v)) return SF_OK;
  if (cJSON_IsObject(v) || cJSON_IsArray(v)) {
    int i = 0;
    for (const cJSON *e = v->child; e; e = e->next, ++i) {
      char epath[SF_JSON_PATH_LEN];
      if (cJSON_IsObject(v))
        sf_json_join_key(epath, sizeof epath, path, e->string);
      else
        sf_json_join_index(epath, sizeof epath, path, i);
      if (check_plain_values(c, e, epath)) return SF_ERR_INPUT;
    }
    return SF_OK;
  }
  return sf_json_fail(c, path, "expected a number, string or object, got %s", sf_json_type_name(v));
}

static int read_optional_object(const sf_json_ctx *c, const cJSON *root, const char *key) {
  const cJSON *v = sf_json_get(root, key);
  if (!v) return SF_OK;
  if (!cJSON_IsObject(v)) return sf_json_fail(c, key, "expected an object, got %s", sf_json_type_name(v));
  return check_plain_values(c, v, key);
}

static int read_atmosphere(const sf_json_ctx *c, const cJSON *root, sf_weights *w) {
  const cJSON *a = sf_json_get(root, "atmosphere");
  if (!a) return sf_json_fail(c, "atmosphere", "missing");
  if (!cJSON_IsObject(a)) return sf_json_fail(c, "atmosphere", "expected an object, got %s", sf_json_type_name(a));
  char *text = sf_json_print_exact(a, 0);
  if (!text) return sf_fail(c->err, SF_ERR_INTERNAL, "%s: out of memory", c->source);
  sf_error inner = {0};
  char name[600];
  snprintf(name, sizeof name, "%s: atmosphere", c->source);
  int rc = sf_atmosphere_load_string(text, name, &w->atmosphere, &inner);
  free(text);
  if (rc) return sf_fail(c->err, inner.status, "%s", inner.message);
  const cJSON *h = sf_json_get(root, "atmosphere_hash");
  if (!h) return sf_json_fail(c, "atmosphere_hash", "missing");
  if (!cJSON_IsString(h)) return sf_json_fail(c, "atmosphere_hash", "expected a string, got %s", sf_json_type_name(h));
  sf_atmosphere_hash_hex(&w->atmosphere, w->atmosphere_hash);
  if (strcmp(h->valuestring, w->atmosphere_hash) != 0)
    return sf_json_fail(c, "atmosphere_hash",
                        "\"%.40s\" does not match the atmosphere in the file (its hash is %s): the file was edited "
                        "or is stale; refit the model",
                        h->valuestring, w->atmosphere_hash);
  return SF_OK;
}

int sf_weights_load_string(const char *json, const char *source_name, const char *expected_model,
                           sf_weights *out, sf_error *err) {
  memset(out, 0, sizeof *out);
  snprintf(out->source, sizeof out->source, "%s", source_name ? source_name : "<string>");
  sf_json_ctx c = {out->source, err};
  cJSON *root = NULL;
  if (sf_json_parse(&c, json, &root)) return err ? err->status : SF_ERR_INPUT;
  int rc = SF_ERR_INPUT;
  if (!cJSON_IsObject(root)) {
    sf_json_fail(&c, "(file)", "expected a JSON object, got %s", sf_json_type_name(root));
    goto fail;
  }
  if (sf_json_check_keys(&c, root, "", top_keys)) goto fail;
  const cJSON *version = sf_json_get(root, "skyfit_weights");
  if (!version) {
    sf_json_fail(&c, "skyfit_weights", "missing (not a skyfit weights file?)");
    goto fail;
  }
  if (!cJSON_IsNumber(version) || version->valuedouble != SF_WEIGHTS_FORMAT_VERSION) {
    sf_json_fail(&c, "skyfit_weights", "unsupported format version (this skyfit reads %d)", SF_WEIGHTS_FORMAT_VERSION);
    goto fail;
  }
  if (read_name(&c, root, "model", out->model, sizeof out->model) ||
      read_name(&c, root, "quantity", out->quantity, sizeof out->quantity))
    goto fail;
  if (expected_model && strcmp(expected_model, out->model) != 0) {
    sf_json_fail(&c, "model", "expected a \"%s\" model, got \"%s\"", expected_model, out->model);
    goto fail;
  }
  /* The models skyfit writes give one quantity each (a generic "mlp" any). */
  static const char *const model_quantity[][2] = {
      {"sigmoid", "transmittance"}, {"mlp-transmittance", "transmittance"}, {"mlp-scattering", "sky_radiance"},
      {"preetham", "sky_radiance"}, {"hosek", "sky_radiance"},              {"spectral4", "sky_radiance"}};
  for (size_t k = 0; k < sizeof model_quantity / sizeof model_quantity[0]; ++k)
    if (strcmp(out->model, model_quantity[k][0]) == 0 && strcmp(out->quantity, model_quantity[k][1]) != 0) {
      sf_json_fail(&c, "quantity", "a \"%s\" model gives \"%s\", got \"%s\"", out->model, model_quantity[k][1],
                   out->quantity);
      goto fail;
    }
  if (read_atmosphere(&c, root, out) || read_domain(&c, root, &out->domain) || read_inputs(&c, root, out) ||
      read_params(&c, root) || read_optional_object(&c, root, "metrics") ||
      read_optional_object(&c, root, "training"))
    goto fail;
  out->n_params = cJSON_GetArraySize(sf_json_get(root, "params"));
  out->params_read = calloc((size_t)out->n_params + 1, 1);
  if (!out->params_read) {
    sf_fail(err, SF_ERR_INTERNAL, "%s: out of memory", out->source);
    goto fail;
  }
  out->root = root;
  return SF_OK;
fail:
  rc = err && err->status != SF_OK ? err->status : SF_ERR_INPUT;
  cJSON_Delete(root);
  memset(out, 0, sizeof *out);
  return rc;
}

int sf_weights_load_file(const char *path, const char *expected_model, sf_weights *out, sf_error *err) {
  memset(out, 0, sizeof *out);
  static const sf_json_file_rules rules = {"weights file", "", SF_WEIGHTS_MAX_BYTES};
  char *text = NULL;
  int rc = sf_json_read_file(path, &rules, &text, err);
  if (rc) return rc;
  rc = sf_weights_load_string(text, path, expected_model, out, err);
  free(text);
  return rc;
}

void sf_weights_free(sf_weights *w) {
  if (!w) return;
  cJSON_Delete(w->root);
  w->root = NULL;
  free(w->params_read);
  w->params_read = NULL;
  w->n_params = 0;
}

static void shape_text(char *buf, size_t n, int n_dims, const int *shape) {
  if (n_dims == 0) {
    snprintf(buf, n, "a single number");
    return;
  }
  size_t used = 0;
  buf[0] = '\0';
  for (int k = 0; k < n_dims && used < n; ++k) {
    int w = shape[k] < 0 ? snprintf(buf + used, n - used, "%sN", k ? "x" : "")
                         : snprintf(buf + used, n - used, "%s%d", k ? "x" : "", shape[k]);
    if (w < 0) return;
    used += (size_t)w;
  }
}

static void flatten(const cJSON *v, double *values, int *k) {
  if (cJSON_IsNumber(v)) {
    values[(*k)++] = v->valuedouble;
    return;
  }
  for (const cJSON *e = v->child; e; e = e->next) flatten(e, values, k);
}

int sf_weights_param(const sf_weights *w, const char *name, int n_dims, int *shape, double *values,
                     int n_values, sf_error *err) {
  sf_json_ctx c = {w->source, err};
  char path[SF_JSON_PATH_LEN];
  sf_json_join_key(path, sizeof path, "params", name);
  const cJSON *params = sf_json_get(w->root, "params");
  const cJSON *v = sf_json_get(params, name);
  if (!v) return sf_json_fail(&c, path, "missing");
  int index = 0;
  for (const cJSON *e = params->child; e != v; e = e->next) ++index;
  if (index < w->n_params) w->params_read[index] = 1;
  int dims, got[SF_WEIGHTS_MAX_DIMS];
  if (array_shape(&c, v, path, 0, &dims, got)) return SF_ERR_INPUT;
  int match = dims == n_dims;
  for (int k = 0; match && k < n_dims; ++k)
    if (shape[k] >= 0 && shape[k] != got[k]) match = 0;
  if (!match) {
    char want[64], have[64];
    shape_text(want, sizeof want, n_dims, shape);
    shape_text(have, sizeof have, dims, got);
    return sf_json_fail(&c, path, "expected an array of shape %s, got %s", want, have);
  }
  long long count = 1;
  for (int k = 0; k < dims; ++k) count *= got[k];
  if (count > n_values) return sf_json_fail(&c, path, "too many values (%lld, at most %d)", count, n_values);
  for (int k = 0; k < n_dims; ++k) shape[k] = got[k];
  int filled = 0;
  flatten(v, values, &filled);
  return SF_OK;
}

int sf_weights_check_params_read(const sf_weights *w, sf_error *err) {
  const cJSON *params = sf_json_get(w->root, "params");
  int i = 0;
  for (const cJSON *e = params ? params->child : NULL; e; e = e->next, ++i)
    if (i >= w->n_params || !w->params_read[i])
      return sf_fail(err, SF_ERR_INPUT,
                     "%s: params.%s: not a parameter of this %s model (misspelt, or left from another model?)",
                     w->source, e->string, w->model);
  return SF_OK;
}

double sf_weights_metric(const sf_weights *w, const char *name) {
  const cJSON *v = sf_json_get(sf_json_get(w->root, "metrics"), name);
  return cJSON_IsNumber(v) ? v->valuedouble : NAN;
}

int sf_weights_check_fixed_inputs(const sf_weights *w, const sf_weights_input *expected, int n, sf_error *err) {
  if (w->n_inputs == 0) return SF_OK;
  if (w->n_inputs != n)
    return sf_fail(err, SF_ERR_INPUT, "%s: inputs: a %s model has %d input(s), the file declares %d", w->source,
                   w->model, n, w->n_inputs);
  for (int i = 0; i < n; ++i) {
    const sf_weights_input *got = &w->inputs[i], *want = &expected[i];
    if (strcmp(got->name, want->name) != 0)
      return sf_fail(err, SF_ERR_INPUT, "%s: inputs[%d].name: expected \"%s\" for a %s model, got \"%s\"",
                     w->source, i, want->name, w->model, got->name);
    if (got->offset != want->offset || got->scale != want->scale)
      return sf_fail(err, SF_ERR_INPUT,
                     "%s: inputs[%d]: a %s model's %s is normalised with offset %.15g and scale %.15g, not "
                     "offset %.15g and scale %.15g",
                     w->source, i, w->model, want->name, want->offset, want->scale, got->offset, got->scale);
  }
  return SF_OK;
}
