#include "models/spectral_recipes_json.h"

#include <math.h>
#include <string.h>

#include "models/spectral_recipes.h"

/* A finite number under key; `fallback` when absent and optional
 * (isnan(fallback) means required). Must be > 0 when positive is set, >= 0
 * otherwise. */
static int read_param(const sf_json_ctx *c, const cJSON *v, const char *path, const char *key, double fallback,
                      int positive, double *out) {
  char kpath[SF_JSON_PATH_LEN];
  sf_json_join_key(kpath, sizeof kpath, path, key);
  const cJSON *x = sf_json_get(v, key);
  if (!x) {
    if (isnan(fallback)) return sf_json_fail(c, kpath, "missing required key");
    *out = fallback;
    return 0;
  }
  if (sf_json_read_finite(c, x, kpath, out)) return SF_ERR_INPUT;
  if (positive && !(*out > 0.0)) return sf_json_fail(c, kpath, "must be > 0, got %.17g", *out);
  if (!positive && *out < 0.0) return sf_json_fail(c, kpath, "negative value %.17g (must be >= 0)", *out);
  return 0;
}

static int table_failed(const sf_json_ctx *c, const char *path, const sf_error *table_err) {
  return sf_json_fail(c, path, "%s", table_err->message);
}

int sf_read_recipe(const sf_json_ctx *c, const cJSON *v, const char *path, const sf_atmosphere *atm,
                   const sf_constituent *owner, sf_recipe_target target, double *out) {
  char rpath[SF_JSON_PATH_LEN];
  sf_json_join_key(rpath, sizeof rpath, path, "recipe");
  const cJSON *name = sf_json_get(v, "recipe");
  if (!name) return sf_json_fail(c, rpath, "missing required key (an object here is a recipe)");
  if (!cJSON_IsString(name)) return sf_json_fail(c, rpath, "expected a string, got %s", sf_json_type_name(name));
  const char *r = name->valuestring;
  if (!atm->spectral)
    return sf_json_fail(c, rpath, "recipe \"%s\" needs spectral channels (\"channels\": {\"wavelengths_nm\": [...]})", r);
  int n = atm->n_channels;
  const double *nm = atm->wavelengths_nm;
  sf_error table_err = {0};
  double a, b, e;
  if (target == SF_RECIPE_FOR_SUN) {
    if (strcmp(r, "solar_astm_g173") != 0)
      return sf_json_fail(c, rpath, "unknown sun recipe \"%s\" (known: solar_astm_g173)", r);
    static const char *const keys[] = {"recipe", "bin_nm", "scale", NULL};
    if (sf_json_check_keys(c, v, path, keys) || read_param(c, v, path, "bin_nm", 5.0, 1, &a) ||
        read_param(c, v, path, "scale", 1.0, 0, &b))
      return SF_ERR_INPUT;
    return sf_recipe_solar_astm_g173(n, nm, a, b, out, &table_err) ? table_failed(c, path, &table_err) : 0;
  }
  if (strcmp(r, "rayleigh_bucholtz") == 0) {
    static const char *const keys[] = {"recipe", "scale", NULL};
    if (sf_json_check_keys(c, v, path, keys) || read_param(c, v, path, "scale", 1.0, 0, &a)) return SF_ERR_INPUT;
    return sf_recipe_rayleigh_bucholtz(n, nm, a, out, &table_err) ? table_failed(c, path, &table_err) : 0;
  }
  if (strcmp(r, "rayleigh_lambda4") == 0) {
    static const char *const keys[] = {"recipe", "reference_nm", "reference_per_km", NULL};
    if (sf_json_check_keys(c, v, path, keys) || read_param(c, v, path, "reference_nm", NAN, 1, &a) ||
        read_param(c, v, path, "reference_per_km", NAN, 0, &b))
      return SF_ERR_INPUT;
    for (int i = 0; i < n; ++i) out[i] = sf_rayleigh_lambda4_per_km(nm[i], a, b);
    return 0;
  }
  if (strcmp(r, "rayleigh_formula") == 0) {
    static const char *const keys[] = {"recipe", "refractive_index", "number_density_per_m3", NULL};
    if (sf_json_check_keys(c, v, path, keys) || read_param(c, v, path, "refractive_index", NAN, 1, &a) ||
        read_param(c, v, path, "number_density_per_m3", NAN, 1, &b))
      return SF_ERR_INPUT;
    /* (n^2 - 1)^2 is positive below 1 too: n 0.5 gave a dense blue haze */
    if (!(a > 1.0)) {
      char kpath[SF_JSON_PATH_LEN];
      sf_json_join_key(kpath, sizeof kpath, path, "refractive_index");
      return sf_json_fail(c, kpath, "must be > 1 (a gas's refractive index), got %.17g", a);
    }
    for (int i = 0; i < n; ++i) out[i] = sf_rayleigh_formula_per_km(nm[i], a, b);
    return 0;
  }
  if (strcmp(r, "ozone_cross_section") == 0) {
    static const char *const keys[] = {"recipe", "column_du", NULL};
    if (sf_json_check_keys(c, v, path, keys) || read_param(c, v, path, "column_du", NAN, 0, &a))
      return SF_ERR_INPUT;
    double column_km = sf_density_column_km(owner, atm->top_radius_km - atm->bottom_radius_km);
    if (!(column_km > 0.0))
      return sf_json_fail(c, path, "recipe \"ozone_cross_section\": the constituent's density integrates to 0");
    return sf_recipe_ozone_cross_section(n, nm, sf_ozone_peak_number_density(a, column_km), out, &table_err)
               ? table_failed(c, path, &table_err)
               : 0;
  }
  if (strcmp(r, "angstrom") == 0) {
    static const char *const keys[] = {"recipe", "reference_nm", "reference_per_km", "exponent", NULL};
    if (sf_json_check_keys(c, v, path, keys) || read_param(c, v, path, "reference_nm", NAN, 1, &a) ||
        read_param(c, v, path, "reference_per_km", NAN, 0, &b))
      return SF_ERR_INPUT;
    char epath[SF_JSON_PATH_LEN];
    sf_json_join_key(epath, sizeof epath, path, "exponent");
    const cJSON *x = sf_json_get(v, "exponent");
    e = 0.0;
    if (x && sf_json_read_finite(c, x, epath, &e)) return SF_ERR_INPUT;
    for (int i = 0; i < n; ++i) out[i] = sf_angstrom_per_km(nm[i], a, b, e);
    return 0;
  }
  if (strcmp(r, "constant") == 0) {
    static const char *const keys[] = {"recipe", "value", NULL};
    if (sf_json_check_keys(c, v, path, keys) || read_param(c, v, path, "value", NAN, 0, &a)) return SF_ERR_INPUT;
    for (int i = 0; i < n; ++i) out[i] = a;
    return 0;
  }
  return sf_json_fail(c, rpath,
                      "unknown recipe \"%s\" (known: rayleigh_bucholtz, rayleigh_lambda4, rayleigh_formula, "
                      "ozone_cross_section, angstrom, constant)", r);
}
