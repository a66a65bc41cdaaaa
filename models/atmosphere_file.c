/* Loading an atmosphere file (SPEC §4): parse with cJSON, merge over the
 * built-in default when the file says "base": "default", then validate every
 * key into an sf_atmosphere. Each failure names the source, the key path and
 * the problem on one line. */
#include "models/atmosphere_file.h"

#include <cjson/cJSON.h>
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "models/phase.h"

#define PATH_LEN 320
#define MAX_FILE_BYTES ((size_t)64 << 20)

typedef struct load_ctx {
  const char *source;
  sf_error *err;
} load_ctx;

static int input_error(const load_ctx *c, const char *path, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;

static int input_error(const load_ctx *c, const char *path, const char *fmt, ...) {
  char problem[800];
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(problem, sizeof problem, fmt, ap);
  va_end(ap);
  sf_fail(c->err, SF_ERR_INPUT, "%s: %s: %s", c->source, path, problem);
  return SF_ERR_INPUT;
}

static const char *json_type_name(const cJSON *v) {
  if (cJSON_IsNumber(v)) return "a number";
  if (cJSON_IsString(v)) return "a string";
  if (cJSON_IsArray(v)) return "an array";
  if (cJSON_IsObject(v)) return "an object";
  if (cJSON_IsBool(v)) return "a boolean";
  if (cJSON_IsNull(v)) return "null";
  return "an invalid value";
}

static const cJSON *get_key(const cJSON *obj, const char *key) {
  return cJSON_GetObjectItemCaseSensitive(obj, key);
}

/* Key paths longer than the buffer are cut short, never overflow. */
static void path_join(char *buf, size_t n, const char *a, const char *sep, const char *b) {
  size_t used = 0;
  const char *parts[3] = {a, sep, b};
  for (int p = 0; p < 3; ++p)
    for (const char *q = parts[p]; *q && used + 1 < n; ++q) buf[used++] = *q;
  buf[used] = '\0';
}

static void join_key(char *buf, size_t n, const char *prefix, const char *key) {
  path_join(buf, n, prefix, prefix[0] ? "." : "", key);
}

static void join_index(char *buf, size_t n, const char *prefix, int i) {
  char index[16];
  snprintf(index, sizeof index, "[%d]", i);
  path_join(buf, n, prefix, "", index);
}

/* ---- generic checks ------------------------------------------------------ */

/* Rejects keys outside `allowed` (NULL-terminated). */
static int check_keys(const load_ctx *c, const cJSON *obj, const char *prefix,
                      const char *const *allowed) {
  for (const cJSON *k = obj->child; k; k = k->next) {
    char path[PATH_LEN];
    join_key(path, sizeof path, prefix, k->string ? k->string : "");
    int known = 0;
    for (int i = 0; allowed[i]; ++i)
      if (k->string && strcmp(k->string, allowed[i]) == 0) known = 1;
    if (!known) {
      char list[512] = "";
      size_t used = 0;
      for (int i = 0; allowed[i] && used < sizeof list; ++i)
        used += (size_t)snprintf(list + used, sizeof list - used, "%s%s", i ? ", " : "",
                                 allowed[i]);
      return input_error(c, path, "unknown key (allowed here: %s)", list);
    }
  }
  return 0;
}

/* cJSON keeps both copies of a key given twice, and only one would be read:
 * reject that anywhere in the user's file, before merging could hide it. */
static int check_duplicate_keys(const load_ctx *c, const cJSON *node, const char *path) {
  int i = 0;
  for (const cJSON *k = node->child; k; k = k->next, ++i) {
    char kpath[PATH_LEN];
    if (cJSON_IsObject(node)) {
      join_key(kpath, sizeof kpath, path, k->string);
      for (const cJSON *e = node->child; e != k; e = e->next)
        if (strcmp(e->string, k->string) == 0)
          return input_error(c, kpath, "duplicate key (given twice in the same object)");
    } else {
      join_index(kpath, sizeof kpath, path, i);
    }
    if (check_duplicate_keys(c, k, kpath)) return SF_ERR_INPUT;
  }
  return 0;
}

static int read_finite(const load_ctx *c, const cJSON *v, const char *path, double *out) {
  if (!cJSON_IsNumber(v)) return input_error(c, path, "expected a number, got %s", json_type_name(v));
  double x = v->valuedouble;
  if (!isfinite(x)) return input_error(c, path, "not a finite number (too large for a double)");
  *out = x == 0.0 ? 0.0 : x; /* -0 and 0 are one value: one canonical text, one hash */
  return 0;
}

static int read_non_negative(const load_ctx *c, const cJSON *v, const char *path, double *out) {
  if (read_finite(c, v, path, out)) return SF_ERR_INPUT;
  if (*out < 0.0) return input_error(c, path, "negative value %.17g (must be >= 0)", *out);
  return 0;
}

/* One non-negative value per channel: an array of n_channels numbers, or a
 * single number meaning the same value in every channel. */
static int read_channel_values(const load_ctx *c, const cJSON *v, const char *path,
                               int n_channels, double *out) {
  if (cJSON_IsNumber(v)) {
    double x = 0.0;
    if (read_non_negative(c, v, path, &x)) return SF_ERR_INPUT;
    for (int ch = 0; ch < n_channels; ++ch) out[ch] = x;
    return 0;
  }
  if (!cJSON_IsArray(v))
    return input_error(c, path, "expected an array of %d numbers (one per channel) or one number, got %s",
                       n_channels, json_type_name(v));
  int n = cJSON_GetArraySize(v);
  if (n != n_channels)
    return input_error(c, path, "expected %d values (one per channel), got %d", n_channels, n);
  int ch = 0;
  for (const cJSON *e = v->child; e; e = e->next, ++ch) {
    char epath[PATH_LEN];
    join_index(epath, sizeof epath, path, ch);
    if (read_non_negative(c, e, epath, &out[ch])) return SF_ERR_INPUT;
  }
  return 0;
}

static int read_name(const load_ctx *c, const cJSON *v, const char *path, size_t capacity,
                     int allow_empty, char *out) {
  if (!cJSON_IsString(v)) return input_error(c, path, "expected a string, got %s", json_type_name(v));
  size_t len = strlen(v->valuestring);
  if (len == 0 && !allow_empty) return input_error(c, path, "empty name");
  if (len >= capacity)
    return input_error(c, path, "name too long (%zu characters, at most %zu)", len, capacity - 1);
  memcpy(out, v->valuestring, len + 1);
  return 0;
}

/* ---- paths in a merged tree ------------------------------------------------ */

/* Where a value of the merged tree came from: a key the user's file sets is
 * named by its path in that file; a key inherited from "base": "default" is
 * named "(base default) <path in the default>". */
typedef struct top_ref {
  const cJSON *merged;
  const cJSON *user; /* the user's root when merged over a base, else NULL */
} top_ref;

static void top_path(char *buf, size_t n, const top_ref *t, const char *key) {
  int inherited = t->user && get_key(t->merged, key) && !get_key(t->user, key);
  snprintf(buf, n, "%s%s", inherited ? "(base default) " : "", key);
}

typedef struct constituent_ref {
  const cJSON *merged;
  const cJSON *user; /* this constituent in the user's file; NULL: inherited whole */
  int merged_index, user_index;
} constituent_ref;

static void constituent_path(char *buf, size_t n, const constituent_ref *r, const char *key) {
  int inherited = r->user == NULL ||
                  (key && get_key(r->merged, key) && !get_key(r->user, key));
  if (inherited)
    snprintf(buf, n, "(base default) constituents[%d]%s%s", r->merged_index, key ? "." : "",
             key ? key : "");
  else
    snprintf(buf, n, "constituents[%d]%s%s", r->user_index, key ? "." : "", key ? key : "");
}

/* ---- channels ----------------------------------------------------------- */

static int read_channels(const load_ctx *c, const cJSON *v, const char *path, sf_atmosphere *atm) {
  if (v == NULL || (cJSON_IsString(v) && strcmp(v->valuestring, "rgb") == 0)) {
    static const char *const rgb[3] = {"r", "g", "b"};
    atm->spectral = 0;
    atm->n_channels = 3;
    for (int ch = 0; ch < 3; ++ch) snprintf(atm->channel_names[ch], sizeof atm->channel_names[ch], "%s", rgb[ch]);
    return 0;
  }
  if (cJSON_IsString(v))
    return input_error(c, path, "unknown channel set \"%s\" (expected \"rgb\" or {\"wavelengths_nm\": [...]})",
                       v->valuestring);
  if (!cJSON_IsObject(v))
    return input_error(c, path, "expected \"rgb\" or {\"wavelengths_nm\": [...]}, got %s", json_type_name(v));
  static const char *const keys[] = {"wavelengths_nm", NULL};
  if (check_keys(c, v, path, keys)) return SF_ERR_INPUT;
  char wpath[PATH_LEN];
  join_key(wpath, sizeof wpath, path, "wavelengths_nm");
  const cJSON *w = get_key(v, "wavelengths_nm");
  if (!w) return input_error(c, wpath, "missing required key");
  if (!cJSON_IsArray(w)) return input_error(c, wpath, "expected an array of numbers, got %s", json_type_name(w));
  int n = cJSON_GetArraySize(w);
  if (n < 1) return input_error(c, wpath, "empty (at least one wavelength is needed)");
  if (n > SF_MAX_CHANNELS)
    return input_error(c, wpath, "too many wavelengths (%d, at most %d)", n, SF_MAX_CHANNELS);
  int ch = 0;
  for (const cJSON *e = w->child; e; e = e->next, ++ch) {
    char epath[PATH_LEN];
    join_index(epath, sizeof epath, wpath, ch);
    double nm;
    if (read_finite(c, e, epath, &nm)) return SF_ERR_INPUT;
    if (nm <= 0.0) return input_error(c, epath, "wavelength must be positive, got %.17g", nm);
    if (ch > 0 && nm <= atm->wavelengths_nm[ch - 1])
      return input_error(c, epath, "wavelengths must be strictly increasing (%.17g after %.17g)", nm,
                         atm->wavelengths_nm[ch - 1]);
    atm->wavelengths_nm[ch] = nm;
    snprintf(atm->channel_names[ch], sizeof atm->channel_names[ch], "%g", nm);
    if (ch > 0 && strcmp(atm->channel_names[ch], atm->channel_names[ch - 1]) == 0)
      return input_error(c, epath, "wavelength %.17g gets the same channel name \"%s\" as the one before",
                         nm, atm->channel_names[ch]);
  }
  atm->spectral = 1;
  atm->n_channels = n;
  return 0;
}

/* ---- phase -------------------------------------------------------------- */

static int read_g(const load_ctx *c, const cJSON *phase, const char *path, const char *key,
                  const char *kind, double *out) {
  char kpath[PATH_LEN];
  join_key(kpath, sizeof kpath, path, key);
  const cJSON *v = get_key(phase, key);
  if (!v) return input_error(c, kpath, "missing required key (phase kind %s needs it)", kind);
  if (read_finite(c, v, kpath, out)) return SF_ERR_INPUT;
  if (!(fabs(*out) < 1.0))
    return input_error(c, kpath, "asymmetry |%s| must be < 1, got %.17g", key, *out);
  return 0;
}

static int read_phase(const load_ctx *c, const cJSON *v, const char *path, sf_phase *out) {
  if (!cJSON_IsObject(v)) return input_error(c, path, "expected an object, got %s", json_type_name(v));
  char kpath[PATH_LEN];
  join_key(kpath, sizeof kpath, path, "kind");
  const cJSON *kind = get_key(v, "kind");
  if (!kind) return input_error(c, kpath, "missing required key");
  if (!cJSON_IsString(kind)) return input_error(c, kpath, "expected a string, got %s", json_type_name(kind));
  sf_phase p = {SF_PHASE_NONE, 0.0, 0.0, 0.0, 0.0};
  static const sf_phase_kind kinds[] = {SF_PHASE_RAYLEIGH, SF_PHASE_ISOTROPIC,
                                        SF_PHASE_HENYEY_GREENSTEIN, SF_PHASE_CORNETTE_SHANKS,
                                        SF_PHASE_DOUBLE_HENYEY_GREENSTEIN};
  for (size_t i = 0; i < sizeof kinds / sizeof kinds[0]; ++i)
    if (strcmp(kind->valuestring, sf_phase_kind_name(kinds[i])) == 0) p.kind = kinds[i];
  if (p.kind == SF_PHASE_NONE)
    return input_error(c, kpath,
                       "unknown phase kind \"%s\" (known: rayleigh, isotropic, henyey_greenstein, "
                       "cornette_shanks, double_henyey_greenstein)", kind->valuestring);
  static const char *const keys_plain[] = {"kind", NULL};
  static const char *const keys_g[] = {"kind", "g", NULL};
  static const char *const keys_double[] = {"kind", "g1", "g2", "f", NULL};
  const char *const *keys = p.kind == SF_PHASE_HENYEY_GREENSTEIN || p.kind == SF_PHASE_CORNETTE_SHANKS
                                ? keys_g
                                : p.kind == SF_PHASE_DOUBLE_HENYEY_GREENSTEIN ? keys_double : keys_plain;
  if (check_keys(c, v, path, keys)) return SF_ERR_INPUT;
  const char *name = kind->valuestring;
  if (keys == keys_g && read_g(c, v, path, "g", name, &p.g)) return SF_ERR_INPUT;
  if (keys == keys_double) {
    /* seed 004 eq. 5: (1-f) HG(g1) + f HG(g2), a convex mix needs f in [0, 1] */
    if (read_g(c, v, path, "g1", name, &p.g1) || read_g(c, v, path, "g2", name, &p.g2))
      return SF_ERR_INPUT;
    char fpath[PATH_LEN];
    join_key(fpath, sizeof fpath, path, "f");
    const cJSON *f = get_key(v, "f");
    if (!f) return input_error(c, fpath, "missing required key (phase kind %s needs it)", name);
    if (read_finite(c, f, fpath, &p.f)) return SF_ERR_INPUT;
    if (!(p.f >= 0.0 && p.f <= 1.0))
      return input_error(c, fpath, "blend weight f must be in [0, 1], got %.17g", p.f);
  }
  *out = p;
  return 0;
}

/* ---- density ------------------------------------------------------------ */

static int read_layer(const load_ctx *c, const cJSON *v, const char *path, int is_last,
                      sf_density_layer *out) {
  if (!cJSON_IsObject(v)) return input_error(c, path, "expected an object, got %s", json_type_name(v));
  static const char *const keys[] = {"width_km", "exp_term", "exp_scale_per_km", "linear_per_km",
                                     "constant", NULL};
  if (check_keys(c, v, path, keys)) return SF_ERR_INPUT;
  double terms[5] = {0, 0, 0, 0, 0}; /* Bruneton 2017: an omitted term is 0 */
  for (int i = 0; i < 5; ++i) {
    const cJSON *t = get_key(v, keys[i]);
    char tpath[PATH_LEN];
    join_key(tpath, sizeof tpath, path, keys[i]);
    if (t && read_finite(c, t, tpath, &terms[i])) return SF_ERR_INPUT;
  }
  char wpath[PATH_LEN];
  join_key(wpath, sizeof wpath, path, "width_km");
  if (!is_last && !(terms[0] > 0.0))
    return input_error(c, wpath, "width must be > 0 in a layer that is not the last, got %.17g", terms[0]);
  if (terms[0] < 0.0) return input_error(c, wpath, "width must be >= 0, got %.17g", terms[0]);
  out->width_km = terms[0];
  out->exp_term = terms[1];
  out->exp_scale_per_km = terms[2];
  out->linear_per_km = terms[3];
  out->constant = terms[4];
  return 0;
}

static int read_density(const load_ctx *c, const cJSON *v, const char *path, sf_constituent *out) {
  if (!cJSON_IsArray(v))
    return input_error(c, path, "expected an array of layers, got %s", json_type_name(v));
  int n = cJSON_GetArraySize(v);
  if (n < 1) return input_error(c, path, "empty (at least one layer is needed)");
  if (n > SF_MAX_LAYERS) return input_error(c, path, "too many layers (%d, at most %d)", n, SF_MAX_LAYERS);
  int i = 0;
  for (const cJSON *e = v->child; e; e = e->next, ++i) {
    char lpath[PATH_LEN];
    join_index(lpath, sizeof lpath, path, i);
    if (read_layer(c, e, lpath, i == n - 1, &out->layers[i])) return SF_ERR_INPUT;
  }
  out->n_layers = n;
  return 0;
}

/* ---- constituents ----------------------------------------------------- */

static int read_constituent(const load_ctx *c, const constituent_ref *r, int n_channels,
                            sf_constituent *out) {
  char path[PATH_LEN];
  constituent_path(path, sizeof path, r, NULL);
  if (!cJSON_IsObject(r->merged)) return input_error(c, path, "expected an object, got %s", json_type_name(r->merged));
  static const char *const keys[] = {"name", "scattering", "absorption", "phase", "density", NULL};
  if (check_keys(c, r->merged, path, keys)) return SF_ERR_INPUT;
  static const char *const required[] = {"name", "scattering", "absorption", "density"};
  for (int i = 0; i < 4; ++i)
    if (!get_key(r->merged, required[i])) {
      constituent_path(path, sizeof path, r, required[i]);
      return input_error(c, path, "missing required key");
    }
  constituent_path(path, sizeof path, r, "name");
  if (read_name(c, get_key(r->merged, "name"), path, sizeof out->name, 0, out->name)) return SF_ERR_INPUT;
  constituent_path(path, sizeof path, r, "scattering");
  if (read_channel_values(c, get_key(r->merged, "scattering"), path, n_channels, out->scattering))
    return SF_ERR_INPUT;
  constituent_path(path, sizeof path, r, "absorption");
  if (read_channel_values(c, get_key(r->merged, "absorption"), path, n_channels, out->absorption))
    return SF_ERR_INPUT;
  constituent_path(path, sizeof path, r, "phase");
  const cJSON *phase = get_key(r->merged, "phase");
  if (phase) {
    if (read_phase(c, phase, path, &out->phase)) return SF_ERR_INPUT;
  } else if (sf_constituent_scatters(out, n_channels)) {
    return input_error(c, path, "missing: a constituent that scatters light (some scattering > 0) needs a phase function");
  } else {
    out->phase.kind = SF_PHASE_NONE;
  }
  constituent_path(path, sizeof path, r, "density");
  return read_density(c, get_key(r->merged, "density"), path, out);
}

/* The user's constituent list must be objects with distinct valid names
 * before "base" merging can match them by name. */
static int check_constituent_names(const load_ctx *c, const cJSON *list) {
  int j = 0;
  for (const cJSON *e = list->child; e; e = e->next, ++j) {
    char path[PATH_LEN], npath[PATH_LEN];
    join_index(path, sizeof path, "constituents", j);
    if (!cJSON_IsObject(e)) return input_error(c, path, "expected an object, got %s", json_type_name(e));
    join_key(npath, sizeof npath, path, "name");
    const cJSON *name = get_key(e, "name");
    if (!name) return input_error(c, npath, "missing required key");
    char buf[SF_NAME_LEN];
    if (read_name(c, name, npath, sizeof buf, 0, buf)) return SF_ERR_INPUT;
    int k = 0;
    for (const cJSON *o = list->child; o != e; o = o->next, ++k)
      if (strcmp(get_key(o, "name")->valuestring, buf) == 0)
        return input_error(c, npath, "duplicate constituent name \"%s\" (also constituents[%d])", buf, k);
  }
  return 0;
}

static const cJSON *find_by_name(const cJSON *list, const char *name, int *index) {
  int i = 0;
  for (const cJSON *e = list ? list->child : NULL; e; e = e->next, ++i) {
    const cJSON *n = get_key(e, "name");
    if (cJSON_IsString(n) && strcmp(n->valuestring, name) == 0) {
      if (index) *index = i;
      return e;
    }
  }
  return NULL;
}

/* ---- the whole file --------------------------------------------------- */

static int read_atmosphere(const load_ctx *c, const top_ref *t, sf_atmosphere *atm) {
  static const char *const keys[] = {"name", "base", "bottom_radius_km", "top_radius_km",
                                     "ground_albedo", "sun_irradiance", "sun_angular_radius_rad",
                                     "channels", "constituents", NULL};
  if (check_keys(c, t->merged, "", keys)) return SF_ERR_INPUT;
  char path[PATH_LEN];
  const cJSON *v;

  top_path(path, sizeof path, t, "name");
  if ((v = get_key(t->merged, "name")) != NULL) {
    if (read_name(c, v, path, sizeof atm->name, 1, atm->name)) return SF_ERR_INPUT;
  } else {
    snprintf(atm->name, sizeof atm->name, "unnamed");
  }

  static const char *const radii[2] = {"bottom_radius_km", "top_radius_km"};
  double r[2];
  for (int i = 0; i < 2; ++i) {
    top_path(path, sizeof path, t, radii[i]);
    if (!(v = get_key(t->merged, radii[i]))) return input_error(c, path, "missing required key");
    if (read_finite(c, v, path, &r[i])) return SF_ERR_INPUT;
    if (!(r[i] > 0.0)) return input_error(c, path, "radius must be positive, got %.17g", r[i]);
  }
  if (!(r[1] > r[0]))
    return input_error(c, path, "must be greater than bottom_radius_km (%.17g), got %.17g", r[0], r[1]);
  atm->bottom_radius_km = r[0];
  atm->top_radius_km = r[1];

  top_path(path, sizeof path, t, "channels");
  if (read_channels(c, get_key(t->merged, "channels"), path, atm)) return SF_ERR_INPUT;

  top_path(path, sizeof path, t, "ground_albedo");
  if ((v = get_key(t->merged, "ground_albedo")) != NULL &&
      read_channel_values(c, v, path, atm->n_channels, atm->ground_albedo))
    return SF_ERR_INPUT;
  top_path(path, sizeof path, t, "sun_irradiance");
  if ((v = get_key(t->merged, "sun_irradiance")) != NULL) {
    if (read_channel_values(c, v, path, atm->n_channels, atm->sun_irradiance)) return SF_ERR_INPUT;
  } else {
    for (int ch = 0; ch < atm->n_channels; ++ch) atm->sun_irradiance[ch] = 1.0; /* SPEC §3 */
  }
  top_path(path, sizeof path, t, "sun_angular_radius_rad");
  atm->sun_angular_radius_rad = SF_DEFAULT_SUN_ANGULAR_RADIUS_RAD;
  if ((v = get_key(t->merged, "sun_angular_radius_rad")) != NULL) {
    if (read_finite(c, v, path, &atm->sun_angular_radius_rad)) return SF_ERR_INPUT;
    if (!(atm->sun_angular_radius_rad >= 0.0 && atm->sun_angular_radius_rad < 1.5707963267948966))
      return input_error(c, path, "angular radius must be in [0, pi/2), got %.17g",
                         atm->sun_angular_radius_rad);
  }

  top_path(path, sizeof path, t, "constituents");
  const cJSON *list = get_key(t->merged, "constituents");
  if (!list) return input_error(c, path, "missing required key");
  if (!cJSON_IsArray(list))
    return input_error(c, path, "expected an array of constituents, got %s", json_type_name(list));
  int n = cJSON_GetArraySize(list);
  if (n < 1) return input_error(c, path, "empty (at least one constituent is needed)");
  if (n > SF_MAX_CONSTITUENTS)
    return input_error(c, path, "too many constituents (%d%s, at most %d)", n,
                       t->user ? " after merging with base \"default\"" : "", SF_MAX_CONSTITUENTS);
  const cJSON *user_list = t->user ? get_key(t->user, "constituents") : list;
  int i = 0;
  for (const cJSON *e = list->child; e; e = e->next, ++i) {
    constituent_ref ref = {e, e, i, i};
    if (t->user) {
      const cJSON *name = get_key(e, "name");
      ref.user = cJSON_IsArray(user_list) && cJSON_IsString(name)
                     ? find_by_name(user_list, name->valuestring, &ref.user_index)
                     : NULL;
    }
    if (read_constituent(c, &ref, atm->n_channels, &atm->constituents[i])) return SF_ERR_INPUT;
  }
  atm->n_constituents = n;
  return 0;
}

/* "base": "default": top-level keys replace the default's; constituents merge
 * by name, a named one overriding just the keys it gives (each key's value is
 * replaced whole, "phase" and "density" included), a new name appended. */
static int merge_over_base(const load_ctx *c, cJSON *merged, const cJSON *user) {
  cJSON *base_list = cJSON_GetObjectItemCaseSensitive(merged, "constituents");
  for (const cJSON *k = user->child; k; k = k->next) {
    if (strcmp(k->string, "base") == 0) continue;
    if (strcmp(k->string, "constituents") == 0 && cJSON_IsArray(k) && cJSON_IsArray(base_list)) {
      for (const cJSON *e = k->child; e; e = e->next) {
        cJSON *target = (cJSON *)find_by_name(base_list, get_key(e, "name")->valuestring, NULL);
        if (!target) {
          cJSON *copy = cJSON_Duplicate(e, 1);
          if (!copy || !cJSON_AddItemToArray(base_list, copy)) goto out_of_memory;
          continue;
        }
        for (const cJSON *ck = e->child; ck; ck = ck->next) {
          cJSON *copy = cJSON_Duplicate(ck, 1);
          if (!copy) goto out_of_memory;
          cJSON_DeleteItemFromObjectCaseSensitive(target, ck->string);
          if (!cJSON_AddItemToObject(target, ck->string, copy)) goto out_of_memory;
        }
      }
      continue;
    }
    cJSON *copy = cJSON_Duplicate(k, 1);
    if (!copy) goto out_of_memory;
    cJSON_DeleteItemFromObjectCaseSensitive(merged, k->string);
    if (!cJSON_AddItemToObject(merged, k->string, copy)) goto out_of_memory;
  }
  return 0;
out_of_memory:
  return sf_fail(c->err, SF_ERR_INTERNAL, "%s: out of memory while merging over base \"default\"", c->source);
}

static int load_tree(const load_ctx *c, const cJSON *user, sf_atmosphere *out) {
  if (!cJSON_IsObject(user))
    return input_error(c, "(root)", "expected a JSON object, got %s", json_type_name(user));
  if (check_duplicate_keys(c, user, "")) return SF_ERR_INPUT;
  const cJSON *list = get_key(user, "constituents");
  if (cJSON_IsArray(list) && check_constituent_names(c, list)) return SF_ERR_INPUT;
  top_ref t = {user, NULL};
  cJSON *merged = NULL;
  const cJSON *base = get_key(user, "base");
  if (base) {
    if (!cJSON_IsString(base)) return input_error(c, "base", "expected a string, got %s", json_type_name(base));
    if (strcmp(base->valuestring, "default") != 0)
      return input_error(c, "base", "unknown base \"%s\" (the only base is \"default\")", base->valuestring);
    merged = cJSON_Parse(sf_atmosphere_default_json());
    if (!merged) return sf_fail(c->err, SF_ERR_INTERNAL, "%s: cannot parse the built-in default atmosphere", c->source);
    if (merge_over_base(c, merged, user)) {
      cJSON_Delete(merged);
      return SF_ERR_INTERNAL;
    }
    t.merged = merged;
    t.user = user;
  }
  sf_atmosphere *atm = calloc(1, sizeof *atm); /* zero: unused entries compare equal */
  int rc = atm ? read_atmosphere(c, &t, atm)
               : sf_fail(c->err, SF_ERR_INTERNAL, "%s: out of memory", c->source);
  if (rc == 0) {
    sf_atmosphere_finalize(atm);
    *out = *atm;
  }
  free(atm);
  cJSON_Delete(merged);
  return rc;
}

/* cJSON reports where parsing stopped; people want line and column. */
static int syntax_error(const load_ctx *c, const char *text, const char *stop) {
  if (!stop) stop = text;
  int line = 1;
  const char *line_start = text;
  for (const char *p = text; p < stop && *p; ++p)
    if (*p == '\n') {
      ++line;
      line_start = p + 1;
    }
  char where[64], near[24];
  snprintf(where, sizeof where, "line %d, column %d", line, (int)(stop - line_start) + 1);
  size_t n = 0;
  while (n + 1 < sizeof near && stop[n] && stop[n] != '\n' && stop[n] != '\r') {
    near[n] = (unsigned char)stop[n] < 0x20 ? ' ' : stop[n];
    ++n;
  }
  near[n] = '\0';
  if (n == 0 && *stop == '\0') return input_error(c, where, "JSON syntax error: unexpected end of input");
  return input_error(c, where, "JSON syntax error near '%s'", near);
}

int sf_atmosphere_load_string(const char *json_text, const char *source_name, sf_atmosphere *out,
                              sf_error *err) {
  load_ctx c = {source_name ? source_name : "<string>", err};
  if (!json_text) return input_error(&c, "(root)", "no JSON text");
  const char *stop = NULL;
  cJSON *user = cJSON_ParseWithOpts(json_text, &stop, 1);
  if (!user) return syntax_error(&c, json_text, stop);
  int rc = load_tree(&c, user, out);
  cJSON_Delete(user);
  return rc;
}

/* The whole file as one NUL-terminated string. */
static int read_whole_file(const char *path, char **text_out, sf_error *err) {
  FILE *f = fopen(path, "rb");
  if (!f) return sf_fail(err, SF_ERR_INPUT, "%s: cannot open atmosphere file: %s", path, strerror(errno));
  size_t cap = 0, len = 0;
  char *text = NULL;
  int rc = 0;
  for (;;) {
    if (len + 1 >= cap) {
      size_t new_cap = cap ? 2 * cap : (size_t)1 << 16;
      if (new_cap > MAX_FILE_BYTES) {
        rc = sf_fail(err, SF_ERR_INPUT, "%s: atmosphere file too large (over %zu bytes)", path,
                     MAX_FILE_BYTES);
        break;
      }
      char *grown = realloc(text, new_cap);
      if (!grown) {
        rc = sf_fail(err, SF_ERR_INTERNAL, "%s: out of memory reading the file", path);
        break;
      }
      text = grown;
      cap = new_cap;
    }
    size_t got = fread(text + len, 1, cap - 1 - len, f);
    len += got;
    if (got == 0) {
      if (ferror(f))
        rc = sf_fail(err, SF_ERR_INPUT, "%s: cannot read atmosphere file: %s", path, strerror(errno));
      break;
    }
  }
  fclose(f);
  if (rc) {
    free(text);
    return rc;
  }
  text[len] = '\0';
  if (strlen(text) != len) {
    rc = sf_fail(err, SF_ERR_INPUT, "%s: byte %zu: NUL byte in a JSON file", path, strlen(text));
    free(text);
    return rc;
  }
  *text_out = text;
  return 0;
}

int sf_atmosphere_load_file(const char *path, sf_atmosphere *out, sf_error *err) {
  char *text = NULL;
  int rc = read_whole_file(path, &text, err);
  if (rc) return rc;
  rc = sf_atmosphere_load_string(text, path, out, err);
  free(text);
  return rc;
}
