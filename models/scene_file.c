/* Loading a scene file (SPEC §5): parse with cJSON, start from the built-in
 * scene, let each given key replace its value after validation, then load the
 * atmosphere the scene names. Messages follow the atmosphere file's form
 * (SPEC §4): "<source>: <key path>: <problem>" on one line. */
#include "models/scene_file.h"

#include <cjson/cJSON.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "models/atmosphere_file.h"
#include "util/json_read.h"

#define MAX_SCENE_FILE_BYTES ((size_t)1 << 20)

typedef struct scene_ctx {
  sf_json_ctx json;
  const char *base_dir;
} scene_ctx;

/* [min, max] of finite numbers, each within [lo, hi], min <= max. */
static int read_range(const sf_json_ctx *c, const cJSON *v, const char *key, double lo, double hi,
                      const char *bounds_text, double out[2]) {
  if (!cJSON_IsArray(v))
    return sf_json_fail(c, key, "expected an array [min, max] of two numbers, got %s", sf_json_type_name(v));
  int n = cJSON_GetArraySize(v);
  if (n != 2) return sf_json_fail(c, key, "expected an array [min, max] of two numbers, got %d values", n);
  double r[2];
  int i = 0;
  for (const cJSON *e = v->child; e; e = e->next, ++i) {
    char path[128];
    snprintf(path, sizeof path, "%s[%d]", key, i);
    if (sf_json_read_finite(c, e, path, &r[i])) return SF_ERR_INPUT;
    if (!(r[i] >= lo && r[i] <= hi)) return sf_json_fail(c, path, "must be %s, got %.17g", bounds_text, r[i]);
  }
  if (!(r[0] <= r[1]))
    return sf_json_fail(c, key, "empty domain: min %.17g is greater than max %.17g", r[0], r[1]);
  out[0] = r[0];
  out[1] = r[1];
  return 0;
}

/* One of `names` (NULL-terminated); returns its index in *index. */
static int read_choice(const sf_json_ctx *c, const cJSON *v, const char *path,
                       const char *const *names, int *index) {
  if (!cJSON_IsString(v)) return sf_json_fail(c, path, "expected a string, got %s", sf_json_type_name(v));
  char list[200] = "";
  size_t used = 0;
  for (int i = 0; names[i]; ++i) {
    if (strcmp(v->valuestring, names[i]) == 0) {
      *index = i;
      return 0;
    }
    used += (size_t)snprintf(list + used, sizeof list - used, "%s%s", i ? ", " : "", names[i]);
  }
  return sf_json_fail(c, path, "unknown value \"%s\" (known: %s)", v->valuestring, list);
}

/* A path in the scene file, made relative to the scene file's folder. */
static int resolve_path(const scene_ctx *c, const cJSON *v, const char *path,
                        char out[SF_SCENE_PATH_LEN]) {
  if (!cJSON_IsString(v)) return sf_json_fail(&c->json, path, "expected a file path (a string), got %s", sf_json_type_name(v));
  const char *rel = v->valuestring;
  if (rel[0] == '\0') return sf_json_fail(&c->json, path, "empty file path");
  int absolute = rel[0] == '/';
  const char *dir = absolute || !c->base_dir ? "" : c->base_dir;
  size_t dir_len = strlen(dir);
  const char *sep = dir_len > 0 && dir[dir_len - 1] != '/' ? "/" : "";
  int n = snprintf(out, SF_SCENE_PATH_LEN, "%s%s%s", dir, sep, rel);
  if (n < 0 || n >= SF_SCENE_PATH_LEN)
    return sf_json_fail(&c->json, path, "resolved path too long (%d characters, at most %d)", n, SF_SCENE_PATH_LEN - 1);
  return 0;
}

static int read_quantities(const sf_json_ctx *c, const cJSON *v, unsigned *out) {
  static const char *const names[] = {"sky_radiance", "transmittance", NULL};
  static const unsigned flags[] = {SF_QUANTITY_SKY_RADIANCE, SF_QUANTITY_TRANSMITTANCE};
  if (!cJSON_IsArray(v))
    return sf_json_fail(c, "quantities", "expected an array of names, got %s", sf_json_type_name(v));
  if (cJSON_GetArraySize(v) == 0)
    return sf_json_fail(c, "quantities", "empty (name at least one of: sky_radiance, transmittance)");
  unsigned q = 0;
  int i = 0;
  for (const cJSON *e = v->child; e; e = e->next, ++i) {
    char path[64];
    snprintf(path, sizeof path, "quantities[%d]", i);
    int k = 0;
    if (read_choice(c, e, path, names, &k)) return SF_ERR_INPUT;
    if (q & flags[k]) return sf_json_fail(c, path, "\"%s\" given twice", names[k]);
    q |= flags[k];
  }
  *out = q;
  return 0;
}

static int read_budget(const sf_json_ctx *c, const cJSON *v, sf_scene *s) {
  if (!cJSON_IsObject(v)) return sf_json_fail(c, "error_budget", "expected an object, got %s", sf_json_type_name(v));
  static const char *const keys[] = {"transmittance_rmse", "sky_radiance_rel_rmse", NULL};
  if (sf_json_check_keys(c, v, "error_budget", keys)) return SF_ERR_INPUT;
  double *targets[2] = {&s->transmittance_rmse_budget, &s->sky_radiance_rel_rmse_budget};
  for (int i = 0; i < 2; ++i) {
    const cJSON *b = sf_json_get(v, keys[i]);
    if (!b) continue;
    char path[64];
    snprintf(path, sizeof path, "error_budget.%s", keys[i]);
    double x = 0.0;
    if (sf_json_read_finite(c, b, path, &x)) return SF_ERR_INPUT;
    /* a tiny budget is legal: the build reports that no model meets it */
    if (!(x > 0.0)) return sf_json_fail(c, path, "budget must be > 0, got %.17g", x);
    *targets[i] = x;
  }
  return 0;
}

static int read_outputs(const scene_ctx *c, const cJSON *v, sf_scene *s) {
  if (!cJSON_IsObject(v)) return sf_json_fail(&c->json, "outputs", "expected an object, got %s", sf_json_type_name(v));
  static const char *const keys[] = {"glsl", "c", NULL};
  if (sf_json_check_keys(&c->json, v, "outputs", keys)) return SF_ERR_INPUT;
  const cJSON *o;
  if ((o = sf_json_get(v, "glsl")) && resolve_path(c, o, "outputs.glsl", s->output_glsl)) return SF_ERR_INPUT;
  if ((o = sf_json_get(v, "c")) && resolve_path(c, o, "outputs.c", s->output_c)) return SF_ERR_INPUT;
  return 0;
}

/* The atmosphere file's own errors pass through whole, behind the key that
 * named the file; a file that does not open is named as resolved. */
static int load_atmosphere(const scene_ctx *c, sf_scene *s) {
  FILE *f = fopen(s->atmosphere_path, "rb");
  if (!f)
    return sf_json_fail(&c->json, "atmosphere", "cannot open atmosphere file \"%s\": %s", s->atmosphere_path,
                       strerror(errno));
  fclose(f);
  sf_error atm_err;
  sf_error_clear(&atm_err);
  if (sf_atmosphere_load_file(s->atmosphere_path, &s->atmosphere, &atm_err) == 0) return 0;
  if (atm_err.status != SF_ERR_INPUT)
    return sf_fail(c->json.err, atm_err.status, "%s: atmosphere: %s", c->json.source, atm_err.message);
  return sf_json_fail(&c->json, "atmosphere", "%s", atm_err.message);
}

static int read_scene(const scene_ctx *c, const cJSON *root, sf_scene *s) {
  if (!cJSON_IsObject(root))
    return sf_json_fail(&c->json, "(root)", "expected a JSON object, got %s", sf_json_type_name(root));
  static const char *const keys[] = {"name", "atmosphere", "viewer_altitude_km", "view",
                                     "sun_elevation_deg", "quantities", "color", "error_budget",
                                     "outputs", NULL};
  if (sf_json_check_keys(&c->json, root, "", keys)) return SF_ERR_INPUT;
  sf_scene_default(s);
  strcpy(s->name, "unnamed");
  const cJSON *v;
  if ((v = sf_json_get(root, "name"))) {
    if (!cJSON_IsString(v)) return sf_json_fail(&c->json, "name", "expected a string, got %s", sf_json_type_name(v));
    size_t len = strlen(v->valuestring);
    if (len >= sizeof s->name)
      return sf_json_fail(&c->json, "name", "too long (%zu characters, at most %zu)", len, sizeof s->name - 1);
    memcpy(s->name, v->valuestring, len + 1);
  }
  if ((v = sf_json_get(root, "viewer_altitude_km")) &&
      read_range(&c->json, v, "viewer_altitude_km", 0.0, INFINITY, ">= 0 km (above the ground)",
                 s->viewer_altitude_km))
    return SF_ERR_INPUT;
  static const char *const views[] = {"all", "above_horizon", NULL};
  static const sf_view_range view_values[] = {SF_VIEW_ALL, SF_VIEW_ABOVE_HORIZON};
  int k = 0;
  if ((v = sf_json_get(root, "view"))) {
    if (read_choice(&c->json, v, "view", views, &k)) return SF_ERR_INPUT;
    s->view = view_values[k];
  }
  if ((v = sf_json_get(root, "sun_elevation_deg")) &&
      read_range(&c->json, v, "sun_elevation_deg", -90.0, 90.0, "in [-90, 90] degrees", s->sun_elevation_deg))
    return SF_ERR_INPUT;
  if ((v = sf_json_get(root, "quantities")) && read_quantities(&c->json, v, &s->quantities)) return SF_ERR_INPUT;
  static const char *const colors[] = {"rgb", "spectral4", NULL};
  static const sf_scene_color color_values[] = {SF_COLOR_RGB, SF_COLOR_SPECTRAL4};
  if ((v = sf_json_get(root, "color"))) {
    if (read_choice(&c->json, v, "color", colors, &k)) return SF_ERR_INPUT;
    s->color = color_values[k];
  }
  if ((v = sf_json_get(root, "error_budget")) && read_budget(&c->json, v, s)) return SF_ERR_INPUT;
  if ((v = sf_json_get(root, "outputs")) && read_outputs(c, v, s)) return SF_ERR_INPUT;
  /* last: the only step that reads another file */
  if ((v = sf_json_get(root, "atmosphere"))) {
    if (resolve_path(c, v, "atmosphere", s->atmosphere_path)) return SF_ERR_INPUT;
    if (load_atmosphere(c, s)) return SF_ERR_INPUT;
  }
  return 0;
}

int sf_scene_load_string(const char *json, const char *source_name, const char *base_dir,
                         sf_scene *out, sf_error *err) {
  scene_ctx c = {{source_name ? source_name : "<string>", err}, base_dir};
  cJSON *root = NULL;
  if (sf_json_parse(&c.json, json, &root)) return SF_ERR_INPUT;
  sf_scene *s = malloc(sizeof *s);
  int rc = s ? read_scene(&c, root, s) : sf_fail(err, SF_ERR_INTERNAL, "%s: out of memory", c.json.source);
  if (rc == 0) *out = *s;
  free(s);
  cJSON_Delete(root);
  return rc;
}

int sf_scene_load_file(const char *path, sf_scene *out, sf_error *err) {
  char *text = NULL;
  static const sf_json_file_rules rules = {"scene file", "(file): ", MAX_SCENE_FILE_BYTES};
  int rc = sf_json_read_file(path, &rules, &text, err);
  if (rc) return rc;
  char dir[SF_SCENE_PATH_LEN] = "";
  const char *slash = strrchr(path, '/');
  if (slash) {
    size_t n = slash == path ? 1 : (size_t)(slash - path); /* "/scene.json" lives in "/" */
    if (n >= sizeof dir) {
      free(text);
      return sf_fail(err, SF_ERR_INPUT, "%s: (file): path too long", path);
    }
    memcpy(dir, path, n);
    dir[n] = '\0';
  }
  rc = sf_scene_load_string(text, path, dir, out, err);
  free(text);
  return rc;
}

const char *sf_view_range_name(sf_view_range v) {
  return v == SF_VIEW_ABOVE_HORIZON ? "above_horizon" : "all";
}

const char *sf_scene_color_name(sf_scene_color c) { return c == SF_COLOR_SPECTRAL4 ? "spectral4" : "rgb"; }
