/* Loading an atmosphere file (SPEC §4): parse with cJSON, merge over the
 * built-in default when the file says "base": "default", then validate every
 * key into an sf_atmosphere. Each failure names the source, the key path and
 * the problem on one line. */
#include "models/atmosphere_file.h"

#include <cjson/cJSON.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "models/phase.h"
#include "models/spectral_recipes_json.h"
#include "util/json_read.h"

#define MAX_FILE_BYTES ((size_t)64 << 20)

/* ---- generic checks ------------------------------------------------------ */

static int read_non_negative(const sf_json_ctx *c, const cJSON *v, const char *path, double *out) {
  if (sf_json_read_finite(c, v, path, out)) return SF_ERR_INPUT;
  if (*out < 0.0) return sf_json_fail(c, path, "negative value %.17g (must be >= 0)", *out);
  return 0;
}

/* One non-negative value per channel: an array of n_channels numbers, or a
 * single number meaning the same value in every channel. */
static int read_channel_values(const sf_json_ctx *c, const cJSON *v, const char *path,
                               int n_channels, double *out) {
  if (cJSON_IsNumber(v)) {
    double x = 0.0;
    if (read_non_negative(c, v, path, &x)) return SF_ERR_INPUT;
    for (int ch = 0; ch < n_channels; ++ch) out[ch] = x;
    return 0;
  }
  if (!cJSON_IsArray(v))
    return sf_json_fail(c, path, "expected an array of %d numbers (one per channel) or one number, got %s",
                       n_channels, sf_json_type_name(v));
  int n = cJSON_GetArraySize(v);
  if (n != n_channels)
    return sf_json_fail(c, path, "expected %d values (one per channel), got %d", n_channels, n);
  int ch = 0;
  for (const cJSON *e = v->child; e; e = e->next, ++ch) {
    char epath[SF_JSON_PATH_LEN];
    sf_json_join_index(epath, sizeof epath, path, ch);
    if (read_non_negative(c, e, epath, &out[ch])) return SF_ERR_INPUT;
  }
  return 0;
}

static int read_name(const sf_json_ctx *c, const cJSON *v, const char *path, size_t capacity,
                     int allow_empty, char *out) {
  if (!cJSON_IsString(v)) return sf_json_fail(c, path, "expected a string, got %s", sf_json_type_name(v));
  size_t len = strlen(v->valuestring);
  if (len == 0 && !allow_empty) return sf_json_fail(c, path, "empty name");
  if (len >= capacity)
    return sf_json_fail(c, path, "name too long (%zu characters, at most %zu)", len, capacity - 1);
  memcpy(out, v->valuestring, len + 1);
  return 0;
}

/* A constituent's name heads CSV columns (skyfit eval: "ozone", "mie_r")
 * and names its single-scattering table's file (data/precompute_single.h):
 * letters, digits, '_', '.' and '-' only ("a,b" had split eval's header;
 * "../x" had been refused only when its table was named, without the file
 * or the key), and not one of eval's input columns, which its output
 * repeats before the constituents' ("mu" had written the column twice, a
 * CSV that eval itself refuses to read). */
static int check_constituent_name(const sf_json_ctx *c, const char *name, const char *path) {
  for (const char *p = name; *p; ++p)
    if (!((*p >= 'a' && *p <= 'z') || (*p >= 'A' && *p <= 'Z') || (*p >= '0' && *p <= '9') || *p == '_' ||
          *p == '.' || *p == '-'))
      return sf_json_fail(c, path,
                          "constituent name \"%s\": letters, digits, '_', '.' and '-' only (it heads CSV columns "
                          "and names its table's file)",
                          name);
  static const char *const input_columns[] = {"h_km", "mu", "mu_s", "nu"};
  for (int i = 0; i < 4; ++i)
    if (strcmp(name, input_columns[i]) == 0)
      return sf_json_fail(c, path,
                          "constituent name \"%s\" is one of skyfit eval's input columns (h_km, mu, mu_s, nu), "
                          "which its CSV output repeats beside the constituents' columns",
                          name);
  return 0;
}

/* Coefficients or sun irradiance: numbers as above, or in spectral mode a
 * recipe object deriving them from the shipped tables
 * (models/spectral_recipes.h); owner: the constituent (density read). */
static int read_values_or_recipe(const sf_json_ctx *c, const cJSON *v, const char *path,
                                 const sf_atmosphere *atm, const sf_constituent *owner,
                                 sf_recipe_target target, double *out) {
  if (!cJSON_IsObject(v)) return read_channel_values(c, v, path, atm->n_channels, out);
  if (sf_read_recipe(c, v, path, atm, owner, target, out)) return SF_ERR_INPUT;
  /* A recipe's parameters can each be finite and still overflow (an
   * Angstrom exponent of 3500 makes (440/550)^-3500 infinite): the derived
   * values must pass the same check as values written out. */
  for (int k = 0; k < atm->n_channels; ++k)
    if (!isfinite(out[k]) || out[k] < 0.0)
      return sf_json_fail(c, path, "the recipe gives %g at %s nm (channel %d); values must be finite and >= 0",
                          out[k], atm->channel_names[k], k);
  return 0;
}

/* A per-channel value inherited from "base": "default" (written for its
 * RGB channels) in a file whose "channels" replace them. Values equal in
 * every channel (the default's Mie, ozone scattering, albedo, sun) mean
 * the same at any channel, as one number does: they carry over. Values
 * that differ are per RGB channel: relabelled as wavelengths they had put
 * red's Rayleigh coefficient at the shortest wavelength, silently. */
static int read_inherited_rgb_values(const sf_json_ctx *c, const cJSON *v, const char *path,
                                     const sf_atmosphere *atm, double *out) {
  double rgb[3];
  if (read_channel_values(c, v, path, 3, rgb)) return SF_ERR_INPUT;
  if (!(rgb[0] == rgb[1] && rgb[1] == rgb[2]))
    return sf_json_fail(c, path,
                        "the default's values [%g, %g, %g] are per RGB channel and do not apply to this "
                        "file's \"channels\"; give them for its channels (values or a recipe)",
                        rgb[0], rgb[1], rgb[2]);
  for (int ch = 0; ch < atm->n_channels; ++ch) out[ch] = rgb[0];
  return 0;
}

/* ---- paths in a merged tree ------------------------------------------------ */

/* Where a value of the merged tree came from: a key the user's file sets is
 * named by its path in that file; a key inherited from "base": "default" is
 * named "(base default) <path in the default>". */
typedef struct top_ref {
  const cJSON *merged;
  const cJSON *user; /* the user's root when merged over a base, else NULL */
  int channels_replaced; /* the user's "channels" differ from the base's */
} top_ref;

static int top_key_inherited(const top_ref *t, const char *key) {
  return t->user && sf_json_get(t->merged, key) && !sf_json_get(t->user, key);
}

static void top_path(char *buf, size_t n, const top_ref *t, const char *key) {
  snprintf(buf, n, "%s%s", top_key_inherited(t, key) ? "(base default) " : "", key);
}

typedef struct constituent_ref {
  const cJSON *merged;
  const cJSON *user; /* this constituent in the user's file; NULL: inherited whole */
  int merged_index, user_index;
  int channels_replaced; /* top_ref's */
} constituent_ref;

static int constituent_key_inherited(const constituent_ref *r, const char *key) {
  return r->user == NULL || (key && sf_json_get(r->merged, key) && !sf_json_get(r->user, key));
}

static void constituent_path(char *buf, size_t n, const constituent_ref *r, const char *key) {
  if (constituent_key_inherited(r, key))
    snprintf(buf, n, "(base default) constituents[%d]%s%s", r->merged_index, key ? "." : "",
             key ? key : "");
  else
    snprintf(buf, n, "constituents[%d]%s%s", r->user_index, key ? "." : "", key ? key : "");
}

/* ---- channels ----------------------------------------------------------- */

static int read_channels(const sf_json_ctx *c, const cJSON *v, const char *path, sf_atmosphere *atm) {
  if (v == NULL || (cJSON_IsString(v) && strcmp(v->valuestring, "rgb") == 0)) {
    static const char *const rgb[3] = {"r", "g", "b"};
    atm->spectral = 0;
    atm->n_channels = 3;
    for (int ch = 0; ch < 3; ++ch) snprintf(atm->channel_names[ch], sizeof atm->channel_names[ch], "%s", rgb[ch]);
    return 0;
  }
  if (cJSON_IsString(v))
    return sf_json_fail(c, path, "unknown channel set \"%s\" (expected \"rgb\" or {\"wavelengths_nm\": [...]})",
                       v->valuestring);
  if (!cJSON_IsObject(v))
    return sf_json_fail(c, path, "expected \"rgb\" or {\"wavelengths_nm\": [...]}, got %s", sf_json_type_name(v));
  static const char *const keys[] = {"wavelengths_nm", NULL};
  if (sf_json_check_keys(c, v, path, keys)) return SF_ERR_INPUT;
  char wpath[SF_JSON_PATH_LEN];
  sf_json_join_key(wpath, sizeof wpath, path, "wavelengths_nm");
  const cJSON *w = sf_json_get(v, "wavelengths_nm");
  if (!w) return sf_json_fail(c, wpath, "missing required key");
  if (!cJSON_IsArray(w)) return sf_json_fail(c, wpath, "expected an array of numbers, got %s", sf_json_type_name(w));
  int n = cJSON_GetArraySize(w);
  if (n < 1) return sf_json_fail(c, wpath, "empty (at least one wavelength is needed)");
  if (n > SF_MAX_CHANNELS)
    return sf_json_fail(c, wpath, "too many wavelengths (%d, at most %d)", n, SF_MAX_CHANNELS);
  int ch = 0;
  for (const cJSON *e = w->child; e; e = e->next, ++ch) {
    char epath[SF_JSON_PATH_LEN];
    sf_json_join_index(epath, sizeof epath, wpath, ch);
    double nm;
    if (sf_json_read_finite(c, e, epath, &nm)) return SF_ERR_INPUT;
    if (nm <= 0.0) return sf_json_fail(c, epath, "wavelength must be positive, got %.17g", nm);
    if (ch > 0 && nm <= atm->wavelengths_nm[ch - 1])
      return sf_json_fail(c, epath, "wavelengths must be strictly increasing (%.17g after %.17g)", nm,
                         atm->wavelengths_nm[ch - 1]);
    atm->wavelengths_nm[ch] = nm;
    snprintf(atm->channel_names[ch], sizeof atm->channel_names[ch], "%g", nm);
    if (ch > 0 && strcmp(atm->channel_names[ch], atm->channel_names[ch - 1]) == 0)
      return sf_json_fail(c, epath, "wavelength %.17g gets the same channel name \"%s\" as the one before",
                         nm, atm->channel_names[ch]);
  }
  atm->spectral = 1;
  atm->n_channels = n;
  return 0;
}

/* ---- phase -------------------------------------------------------------- */

static int read_g(const sf_json_ctx *c, const cJSON *phase, const char *path, const char *key,
                  const char *kind, double *out) {
  char kpath[SF_JSON_PATH_LEN];
  sf_json_join_key(kpath, sizeof kpath, path, key);
  const cJSON *v = sf_json_get(phase, key);
  if (!v) return sf_json_fail(c, kpath, "missing required key (phase kind %s needs it)", kind);
  if (sf_json_read_finite(c, v, kpath, out)) return SF_ERR_INPUT;
  if (!(fabs(*out) < 1.0))
    return sf_json_fail(c, kpath, "|%s| must be < 1 (phase kind %s), got %.17g", key, kind, *out);
  return 0;
}

static int read_phase(const sf_json_ctx *c, const cJSON *v, const char *path, sf_phase *out) {
  if (!cJSON_IsObject(v)) return sf_json_fail(c, path, "expected an object, got %s", sf_json_type_name(v));
  char kpath[SF_JSON_PATH_LEN];
  sf_json_join_key(kpath, sizeof kpath, path, "kind");
  const cJSON *kind = sf_json_get(v, "kind");
  if (!kind) return sf_json_fail(c, kpath, "missing required key");
  if (!cJSON_IsString(kind)) return sf_json_fail(c, kpath, "expected a string, got %s", sf_json_type_name(kind));
  sf_phase p = {SF_PHASE_NONE, 0.0, 0.0, 0.0, 0.0};
  static const sf_phase_kind kinds[] = {SF_PHASE_RAYLEIGH, SF_PHASE_ISOTROPIC,
                                        SF_PHASE_HENYEY_GREENSTEIN, SF_PHASE_CORNETTE_SHANKS,
                                        SF_PHASE_DOUBLE_HENYEY_GREENSTEIN};
  for (size_t i = 0; i < sizeof kinds / sizeof kinds[0]; ++i)
    if (strcmp(kind->valuestring, sf_phase_kind_name(kinds[i])) == 0) p.kind = kinds[i];
  if (p.kind == SF_PHASE_NONE)
    return sf_json_fail(c, kpath,
                       "unknown phase kind \"%s\" (known: rayleigh, isotropic, henyey_greenstein, "
                       "cornette_shanks, double_henyey_greenstein)", kind->valuestring);
  static const char *const keys_plain[] = {"kind", NULL};
  static const char *const keys_g[] = {"kind", "g", NULL};
  static const char *const keys_double[] = {"kind", "g1", "g2", "f", NULL};
  const char *const *keys = p.kind == SF_PHASE_HENYEY_GREENSTEIN || p.kind == SF_PHASE_CORNETTE_SHANKS
                                ? keys_g
                                : p.kind == SF_PHASE_DOUBLE_HENYEY_GREENSTEIN ? keys_double : keys_plain;
  if (sf_json_check_keys(c, v, path, keys)) return SF_ERR_INPUT;
  const char *name = kind->valuestring;
  if (keys == keys_g && read_g(c, v, path, "g", name, &p.g)) return SF_ERR_INPUT;
  if (keys == keys_double) {
    /* seed 004 eq. 5: (1-f) HG(g1) + f HG(g2), a convex mix needs f in [0, 1] */
    if (read_g(c, v, path, "g1", name, &p.g1) || read_g(c, v, path, "g2", name, &p.g2))
      return SF_ERR_INPUT;
    char fpath[SF_JSON_PATH_LEN];
    sf_json_join_key(fpath, sizeof fpath, path, "f");
    const cJSON *f = sf_json_get(v, "f");
    if (!f) return sf_json_fail(c, fpath, "missing required key (phase kind %s needs it)", name);
    if (sf_json_read_finite(c, f, fpath, &p.f)) return SF_ERR_INPUT;
    if (!(p.f >= 0.0 && p.f <= 1.0))
      return sf_json_fail(c, fpath, "blend weight f must be in [0, 1], got %.17g", p.f);
  }
  *out = p;
  return 0;
}

/* ---- density ------------------------------------------------------------ */

static int read_layer(const sf_json_ctx *c, const cJSON *v, const char *path, int is_last,
                      sf_density_layer *out) {
  if (!cJSON_IsObject(v)) return sf_json_fail(c, path, "expected an object, got %s", sf_json_type_name(v));
  static const char *const keys[] = {"width_km", "exp_term", "exp_scale_per_km", "linear_per_km",
                                     "constant", NULL};
  if (sf_json_check_keys(c, v, path, keys)) return SF_ERR_INPUT;
  double terms[5] = {0, 0, 0, 0, 0}; /* Bruneton 2017: an omitted term is 0 */
  for (int i = 0; i < 5; ++i) {
    const cJSON *t = sf_json_get(v, keys[i]);
    char tpath[SF_JSON_PATH_LEN];
    sf_json_join_key(tpath, sizeof tpath, path, keys[i]);
    if (t && sf_json_read_finite(c, t, tpath, &terms[i])) return SF_ERR_INPUT;
  }
  char wpath[SF_JSON_PATH_LEN];
  sf_json_join_key(wpath, sizeof wpath, path, "width_km");
  if (!is_last && !(terms[0] > 0.0))
    return sf_json_fail(c, wpath, "width must be > 0 in a layer that is not the last, got %.17g", terms[0]);
  if (terms[0] < 0.0) return sf_json_fail(c, wpath, "width must be >= 0, got %.17g", terms[0]);
  out->width_km = terms[0];
  out->exp_term = terms[1];
  out->exp_scale_per_km = terms[2];
  out->linear_per_km = terms[3];
  out->constant = terms[4];
  return 0;
}

static int read_density(const sf_json_ctx *c, const cJSON *v, const char *path, sf_constituent *out) {
  if (!cJSON_IsArray(v))
    return sf_json_fail(c, path, "expected an array of layers, got %s", sf_json_type_name(v));
  int n = cJSON_GetArraySize(v);
  if (n < 1) return sf_json_fail(c, path, "empty (at least one layer is needed)");
  if (n > SF_MAX_LAYERS) return sf_json_fail(c, path, "too many layers (%d, at most %d)", n, SF_MAX_LAYERS);
  int i = 0;
  for (const cJSON *e = v->child; e; e = e->next, ++i) {
    char lpath[SF_JSON_PATH_LEN];
    sf_json_join_index(lpath, sizeof lpath, path, i);
    if (read_layer(c, e, lpath, i == n - 1, &out->layers[i])) return SF_ERR_INPUT;
  }
  out->n_layers = n;
  return 0;
}

/* ---- constituents ----------------------------------------------------- */

/* A constituent's "scattering" or "absorption" into values[channel]. */
static int read_coefficients(const sf_json_ctx *c, const constituent_ref *r, const char *key,
                             const sf_atmosphere *atm, const sf_constituent *owner, double *values) {
  char path[SF_JSON_PATH_LEN];
  constituent_path(path, sizeof path, r, key);
  const cJSON *v = sf_json_get(r->merged, key);
  if (r->channels_replaced && constituent_key_inherited(r, key))
    return read_inherited_rgb_values(c, v, path, atm, values);
  return read_values_or_recipe(c, v, path, atm, owner, SF_RECIPE_FOR_COEFFICIENT, values);
}

static int read_constituent(const sf_json_ctx *c, const constituent_ref *r, const sf_atmosphere *atm,
                            sf_constituent *out) {
  int n_channels = atm->n_channels;
  char path[SF_JSON_PATH_LEN];
  constituent_path(path, sizeof path, r, NULL);
  if (!cJSON_IsObject(r->merged)) return sf_json_fail(c, path, "expected an object, got %s", sf_json_type_name(r->merged));
  static const char *const keys[] = {"name", "scattering", "absorption", "phase", "density", NULL};
  if (sf_json_check_keys(c, r->merged, path, keys)) return SF_ERR_INPUT;
  static const char *const required[] = {"name", "scattering", "absorption", "density"};
  for (int i = 0; i < 4; ++i)
    if (!sf_json_get(r->merged, required[i])) {
      constituent_path(path, sizeof path, r, required[i]);
      return sf_json_fail(c, path, "missing required key");
    }
  constituent_path(path, sizeof path, r, "name");
  if (read_name(c, sf_json_get(r->merged, "name"), path, sizeof out->name, 0, out->name)) return SF_ERR_INPUT;
  /* the density first: a recipe (ozone from a column) integrates it */
  constituent_path(path, sizeof path, r, "density");
  if (read_density(c, sf_json_get(r->merged, "density"), path, out)) return SF_ERR_INPUT;
  if (read_coefficients(c, r, "scattering", atm, out, out->scattering) ||
      read_coefficients(c, r, "absorption", atm, out, out->absorption))
    return SF_ERR_INPUT;
  constituent_path(path, sizeof path, r, "phase");
  const cJSON *phase = sf_json_get(r->merged, "phase");
  if (phase) {
    if (read_phase(c, phase, path, &out->phase)) return SF_ERR_INPUT;
  } else if (sf_constituent_scatters(out, n_channels)) {
    return sf_json_fail(c, path, "missing: a constituent that scatters light (some scattering > 0) needs a phase function");
  } else {
    out->phase.kind = SF_PHASE_NONE;
  }
  return 0;
}

/* The user's constituent list must be objects with distinct valid names
 * before "base" merging can match them by name. */
static int check_constituent_names(const sf_json_ctx *c, const cJSON *list) {
  int j = 0;
  for (const cJSON *e = list->child; e; e = e->next, ++j) {
    char path[SF_JSON_PATH_LEN], npath[SF_JSON_PATH_LEN];
    sf_json_join_index(path, sizeof path, "constituents", j);
    if (!cJSON_IsObject(e)) return sf_json_fail(c, path, "expected an object, got %s", sf_json_type_name(e));
    sf_json_join_key(npath, sizeof npath, path, "name");
    const cJSON *name = sf_json_get(e, "name");
    if (!name) return sf_json_fail(c, npath, "missing required key");
    char buf[SF_NAME_LEN];
    if (read_name(c, name, npath, sizeof buf, 0, buf) || check_constituent_name(c, buf, npath)) return SF_ERR_INPUT;
    int k = 0;
    for (const cJSON *o = list->child; o != e; o = o->next, ++k)
      if (strcmp(sf_json_get(o, "name")->valuestring, buf) == 0)
        return sf_json_fail(c, npath, "duplicate constituent name \"%s\" (also constituents[%d])", buf, k);
  }
  return 0;
}

static const cJSON *find_by_name(const cJSON *list, const char *name, int *index) {
  int i = 0;
  for (const cJSON *e = list ? list->child : NULL; e; e = e->next, ++i) {
    const cJSON *n = sf_json_get(e, "name");
    if (cJSON_IsString(n) && strcmp(n->valuestring, name) == 0) {
      if (index) *index = i;
      return e;
    }
  }
  return NULL;
}

/* ---- the whole file --------------------------------------------------- */

static int read_atmosphere(const sf_json_ctx *c, const top_ref *t, sf_atmosphere *atm) {
  static const char *const keys[] = {"name", "base", "bottom_radius_km", "top_radius_km",
                                     "ground_albedo", "sun_irradiance", "sun_angular_radius_rad",
                                     "channels", "constituents", NULL};
  if (sf_json_check_keys(c, t->merged, "", keys)) return SF_ERR_INPUT;
  char path[SF_JSON_PATH_LEN];
  const cJSON *v;

  top_path(path, sizeof path, t, "name");
  if ((v = sf_json_get(t->merged, "name")) != NULL) {
    if (read_name(c, v, path, sizeof atm->name, 1, atm->name)) return SF_ERR_INPUT;
  } else {
    snprintf(atm->name, sizeof atm->name, "unnamed");
  }

  static const char *const radii[2] = {"bottom_radius_km", "top_radius_km"};
  double r[2];
  for (int i = 0; i < 2; ++i) {
    top_path(path, sizeof path, t, radii[i]);
    if (!(v = sf_json_get(t->merged, radii[i]))) return sf_json_fail(c, path, "missing required key");
    if (sf_json_read_finite(c, v, path, &r[i])) return SF_ERR_INPUT;
    if (!(r[i] > 0.0)) return sf_json_fail(c, path, "radius must be positive, got %.17g", r[i]);
    /* squares of distances along rays must stay far from overflow (a top
     * of 1e308 km gave every optical depth 0) */
    if (r[i] > 1e12)
      return sf_json_fail(c, path, "radius must be at most 1e12 km, got %.17g", r[i]);
  }
  if (!(r[1] > r[0]))
    return sf_json_fail(c, path, "must be greater than bottom_radius_km (%.17g), got %.17g", r[0], r[1]);
  atm->bottom_radius_km = r[0];
  atm->top_radius_km = r[1];

  top_path(path, sizeof path, t, "channels");
  if (read_channels(c, sf_json_get(t->merged, "channels"), path, atm)) return SF_ERR_INPUT;

  top_path(path, sizeof path, t, "ground_albedo");
  if ((v = sf_json_get(t->merged, "ground_albedo")) != NULL &&
      (t->channels_replaced && top_key_inherited(t, "ground_albedo")
           ? read_inherited_rgb_values(c, v, path, atm, atm->ground_albedo)
           : read_channel_values(c, v, path, atm->n_channels, atm->ground_albedo)))
    return SF_ERR_INPUT;
  for (int ch = 0; ch < atm->n_channels; ++ch)   /* a ground reflects at most what reaches it */
    if (atm->ground_albedo[ch] > 1.0)
      return sf_json_fail(c, path, "an albedo is at most 1, got %.17g (channel %d)", atm->ground_albedo[ch], ch);
  top_path(path, sizeof path, t, "sun_irradiance");
  if ((v = sf_json_get(t->merged, "sun_irradiance")) != NULL) {
    if (t->channels_replaced && top_key_inherited(t, "sun_irradiance")
            ? read_inherited_rgb_values(c, v, path, atm, atm->sun_irradiance)
            : read_values_or_recipe(c, v, path, atm, NULL, SF_RECIPE_FOR_SUN, atm->sun_irradiance))
      return SF_ERR_INPUT;
  } else {
    for (int ch = 0; ch < atm->n_channels; ++ch) atm->sun_irradiance[ch] = 1.0; /* SPEC §3 */
  }
  top_path(path, sizeof path, t, "sun_angular_radius_rad");
  atm->sun_angular_radius_rad = SF_DEFAULT_SUN_ANGULAR_RADIUS_RAD;
  if ((v = sf_json_get(t->merged, "sun_angular_radius_rad")) != NULL) {
    if (sf_json_read_finite(c, v, path, &atm->sun_angular_radius_rad)) return SF_ERR_INPUT;
    if (!(atm->sun_angular_radius_rad >= 0.0 && atm->sun_angular_radius_rad < 1.5707963267948966))
      return sf_json_fail(c, path, "angular radius must be in [0, pi/2), got %.17g",
                         atm->sun_angular_radius_rad);
  }

  top_path(path, sizeof path, t, "constituents");
  const cJSON *list = sf_json_get(t->merged, "constituents");
  if (!list) return sf_json_fail(c, path, "missing required key");
  if (!cJSON_IsArray(list))
    return sf_json_fail(c, path, "expected an array of constituents, got %s", sf_json_type_name(list));
  int n = cJSON_GetArraySize(list);
  if (n < 1) return sf_json_fail(c, path, "empty (at least one constituent is needed)");
  if (n > SF_MAX_CONSTITUENTS)
    return sf_json_fail(c, path, "too many constituents (%d%s, at most %d)", n,
                       t->user ? " after merging with base \"default\"" : "", SF_MAX_CONSTITUENTS);
  const cJSON *user_list = t->user ? sf_json_get(t->user, "constituents") : list;
  int i = 0;
  for (const cJSON *e = list->child; e; e = e->next, ++i) {
    constituent_ref ref = {e, e, i, i, t->channels_replaced};
    if (t->user) {
      const cJSON *name = sf_json_get(e, "name");
      ref.user = cJSON_IsArray(user_list) && cJSON_IsString(name)
                     ? find_by_name(user_list, name->valuestring, &ref.user_index)
                     : NULL;
    }
    if (read_constituent(c, &ref, atm, &atm->constituents[i])) return SF_ERR_INPUT;
  }
  atm->n_constituents = n;
  return 0;
}

/* "base": "default": top-level keys replace the default's; constituents merge
 * by name, a named one overriding just the keys it gives (each key's value is
 * replaced whole, "phase" and "density" included), a new name appended. */
static int merge_over_base(const sf_json_ctx *c, cJSON *merged, const cJSON *user) {
  cJSON *base_list = cJSON_GetObjectItemCaseSensitive(merged, "constituents");
  for (const cJSON *k = user->child; k; k = k->next) {
    if (strcmp(k->string, "base") == 0) continue;
    if (strcmp(k->string, "constituents") == 0 && cJSON_IsArray(k) && cJSON_IsArray(base_list)) {
      for (const cJSON *e = k->child; e; e = e->next) {
        cJSON *target = (cJSON *)find_by_name(base_list, sf_json_get(e, "name")->valuestring, NULL);
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

static int load_tree(const sf_json_ctx *c, const cJSON *user, sf_atmosphere *out) {
  if (!cJSON_IsObject(user))
    return sf_json_fail(c, "(root)", "expected a JSON object, got %s", sf_json_type_name(user));
  /* anywhere in the user's file, before merging could hide a key given twice */
  if (sf_json_check_duplicate_keys(c, user, "")) return SF_ERR_INPUT;
  const cJSON *list = sf_json_get(user, "constituents");
  if (cJSON_IsArray(list) && check_constituent_names(c, list)) return SF_ERR_INPUT;
  /* Over "base", constituents merge by name: an empty list would change
   * nothing, which is not what writing it means. */
  if (cJSON_IsArray(list) && cJSON_GetArraySize(list) == 0 && sf_json_get(user, "base"))
    return sf_json_fail(c, "constituents", "empty: over base \"default\" constituents merge by name, so an empty "
                                           "list would change nothing (give the ones to add or override, or omit "
                                           "the key)");
  top_ref t = {user, NULL, 0};
  cJSON *merged = NULL;
  const cJSON *base = sf_json_get(user, "base");
  if (base) {
    if (!cJSON_IsString(base)) return sf_json_fail(c, "base", "expected a string, got %s", sf_json_type_name(base));
    if (strcmp(base->valuestring, "default") != 0)
      return sf_json_fail(c, "base", "unknown base \"%s\" (the only base is \"default\")", base->valuestring);
    merged = cJSON_Parse(sf_atmosphere_default_json());
    if (!merged) return sf_fail(c->err, SF_ERR_INTERNAL, "%s: cannot parse the built-in default atmosphere", c->source);
    const cJSON *user_channels = sf_json_get(user, "channels");
    t.channels_replaced = user_channels && !cJSON_Compare(user_channels, sf_json_get(merged, "channels"), 1);
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

int sf_atmosphere_load_string(const char *json_text, const char *source_name, sf_atmosphere *out,
                              sf_error *err) {
  sf_json_ctx c = {source_name ? source_name : "<string>", err};
  cJSON *user = NULL;
  if (sf_json_parse(&c, json_text, &user)) return SF_ERR_INPUT;
  int rc = load_tree(&c, user, out);
  cJSON_Delete(user);
  return rc;
}

int sf_atmosphere_load_file(const char *path, sf_atmosphere *out, sf_error *err) {
  char *text = NULL;
  static const sf_json_file_rules rules = {"atmosphere file", "", MAX_FILE_BYTES};
  int rc = sf_json_read_file(path, &rules, &text, err);
  if (rc) return rc;
  rc = sf_atmosphere_load_string(text, path, out, err);
  free(text);
  return rc;
}
