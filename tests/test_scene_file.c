/* The scene file (SPEC §5): the SPEC's example loads with its exact numbers,
 * relative atmosphere paths resolve against the scene's folder, the built-in
 * scene, the table-coordinate domain against closed forms, and one rejected
 * file per class of invalid input. */
#include "models/scene_file.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "tests/check.h"
#include "util/constants.h"

static char tmp_dir[256];

/* Test JSON is written with single quotes to stay readable in C. */
static void write_file(const char *name, const char *single_quoted) {
  char path[512];
  snprintf(path, sizeof path, "%s/%s", tmp_dir, name);
  FILE *f = fopen(path, "wb");
  for (const char *p = single_quoted; *p; ++p) fputc(*p == '\'' ? '"' : *p, f);
  fclose(f);
}

static char *json_q(const char *text) {
  char *s = malloc(strlen(text) + 1);
  for (size_t i = 0;; ++i) {
    s[i] = text[i] == '\'' ? '"' : text[i];
    if (!text[i]) break;
  }
  return s;
}

static int path_is(const char *got, const char *name) {
  char want[512];
  snprintf(want, sizeof want, "%s/%s", tmp_dir, name);
  printf("     path %s (want %s)\n", got, want);
  return strcmp(got, want) == 0;
}

#define SPEC_EXAMPLE                                                                \
  "{\n"                                                                             \
  "  'name': 'flight-sim',\n"                                                       \
  "  'atmosphere': 'earth.json',\n"                                                 \
  "  'viewer_altitude_km': [0, 15],\n"                                              \
  "  'view': 'all',\n"                                                              \
  "  'sun_elevation_deg': [-10, 90],\n"                                             \
  "  'quantities': ['sky_radiance', 'transmittance'],\n"                            \
  "  'color': 'rgb',\n"                                                             \
  "  'error_budget': {'transmittance_rmse': 1e-3, 'sky_radiance_rel_rmse': 0.05},\n" \
  "  'outputs': {'glsl': 'sky.glsl', 'c': 'sky.h'}\n"                               \
  "}\n"

static void test_spec_example(void) {
  printf("\n-- SPEC §5 example --\n");
  write_file("earth.json", "{'base': 'default'}");
  write_file("flight.json", SPEC_EXAMPLE);
  char path[512];
  snprintf(path, sizeof path, "%s/flight.json", tmp_dir);
  sf_scene *s = calloc(1, sizeof *s);
  sf_error err;
  sf_error_clear(&err);
  int rc = sf_scene_load_file(path, s, &err);
  printf("load %s: rc=%d %s\n", path, rc, rc ? err.message : "(loaded)");
  CHECK(rc == 0);
  CHECK(strcmp(s->name, "flight-sim") == 0);
  CHECK(path_is(s->atmosphere_path, "earth.json"));
  CHECK(strcmp(s->atmosphere.name, "earth-hillaire2020") == 0);
  CHECK_REL(s->atmosphere.bottom_radius_km, 6360.0, 0.0);
  CHECK_REL(s->atmosphere.top_radius_km, 6460.0, 0.0);
  CHECK_REL(s->viewer_altitude_km[0], 0.0, 0.0);
  CHECK_REL(s->viewer_altitude_km[1], 15.0, 0.0);
  CHECK(s->view == SF_VIEW_ALL);
  CHECK_REL(s->sun_elevation_deg[0], -10.0, 0.0);
  CHECK_REL(s->sun_elevation_deg[1], 90.0, 0.0);
  CHECK(s->quantities == (SF_QUANTITY_SKY_RADIANCE | SF_QUANTITY_TRANSMITTANCE));
  CHECK(s->color == SF_COLOR_RGB);
  CHECK_REL(s->transmittance_rmse_budget, 1e-3, 0.0);
  CHECK_REL(s->sky_radiance_rel_rmse_budget, 0.05, 0.0);
  CHECK(path_is(s->output_glsl, "sky.glsl"));
  CHECK(path_is(s->output_c, "sky.h"));
  free(s);
}

static void test_relative_paths(void) {
  printf("\n-- relative paths resolve against the scene's folder --\n");
  char sub[512], scene_path[512];
  snprintf(sub, sizeof sub, "%s/scenes", tmp_dir);
  CHECK(mkdir(sub, 0700) == 0);
  /* a thinner atmosphere, so the test sees which file was read */
  write_file("thin.json", "{'base': 'default', 'top_radius_km': 6420}");
  write_file("scenes/ground.json",
             "{'atmosphere': '../thin.json', 'view': 'above_horizon', 'outputs': {'c': 'out/sky.h'}}");
  snprintf(scene_path, sizeof scene_path, "%s/scenes/ground.json", tmp_dir);
  /* from another working directory: the path must not depend on it */
  char old_cwd[1024];
  CHECK(getcwd(old_cwd, sizeof old_cwd) != NULL);
  CHECK(chdir("/") == 0);
  sf_scene *s = calloc(1, sizeof *s);
  sf_error err;
  sf_error_clear(&err);
  int rc = sf_scene_load_file(scene_path, s, &err);
  printf("load %s: rc=%d %s\n", scene_path, rc, rc ? err.message : "(loaded)");
  CHECK(rc == 0);
  CHECK(path_is(s->atmosphere_path, "scenes/../thin.json"));
  CHECK_REL(s->atmosphere.top_radius_km, 6420.0, 0.0);
  CHECK(path_is(s->output_c, "scenes/out/sky.h"));
  CHECK(s->output_glsl[0] == '\0');
  CHECK(s->view == SF_VIEW_ABOVE_HORIZON);
  /* omitted keys keep the built-in scene's values; the name is "unnamed" */
  CHECK(strcmp(s->name, "unnamed") == 0);
  CHECK_REL(s->viewer_altitude_km[1], 400.0, 0.0);
  CHECK_REL(s->sun_elevation_deg[0], -10.0, 0.0);
  CHECK_REL(s->transmittance_rmse_budget, 1e-3, 0.0);
  CHECK_REL(s->sky_radiance_rel_rmse_budget, 0.05, 0.0);
  CHECK(chdir(old_cwd) == 0);

  /* an absolute path is kept as it is, whatever base_dir says */
  char abs_json[1024];
  snprintf(abs_json, sizeof abs_json, "{\"atmosphere\": \"%s/thin.json\"}", tmp_dir);
  sf_error_clear(&err);
  rc = sf_scene_load_string(abs_json, "abs.json", "/nonexistent/dir", s, &err);
  printf("load abs.json: rc=%d %s\n", rc, rc ? err.message : "(loaded)");
  CHECK(rc == 0);
  CHECK(path_is(s->atmosphere_path, "thin.json"));
  CHECK_REL(s->atmosphere.top_radius_km, 6420.0, 0.0);
  free(s);
}

static void test_default_scene(void) {
  printf("\n-- built-in scene (SPEC §5: ground to space, sun -10..90 deg, RGB) --\n");
  sf_scene *s = calloc(1, sizeof *s);
  sf_scene_default(s);
  CHECK(strcmp(s->name, "default") == 0);
  CHECK(s->atmosphere_path[0] == '\0');
  CHECK(strcmp(s->atmosphere.name, "earth-hillaire2020") == 0);
  CHECK_REL(s->atmosphere.bottom_radius_km, 6360.0, 0.0);
  CHECK_REL(s->atmosphere.top_radius_km, 6460.0, 0.0);
  CHECK_REL(s->viewer_altitude_km[0], 0.0, 0.0);
  CHECK_REL(s->viewer_altitude_km[1], 400.0, 0.0);
  CHECK(s->viewer_altitude_km[1] > s->atmosphere.top_radius_km - s->atmosphere.bottom_radius_km);
  CHECK(s->view == SF_VIEW_ALL);
  CHECK_REL(s->sun_elevation_deg[0], -10.0, 0.0);
  CHECK_REL(s->sun_elevation_deg[1], 90.0, 0.0);
  CHECK(s->quantities == (SF_QUANTITY_SKY_RADIANCE | SF_QUANTITY_TRANSMITTANCE));
  CHECK(s->color == SF_COLOR_RGB);
  CHECK_REL(s->transmittance_rmse_budget, 1e-3, 0.0);
  CHECK_REL(s->sky_radiance_rel_rmse_budget, 0.05, 0.0);
  CHECK(s->output_glsl[0] == '\0' && s->output_c[0] == '\0');
  /* an empty scene file is the built-in scene under another name */
  sf_scene *e = calloc(1, sizeof *e);
  sf_error err;
  sf_error_clear(&err);
  CHECK(sf_scene_load_string("{}", "empty.json", NULL, e, &err) == 0);
  strcpy(e->name, "default");
  CHECK(memcmp(e, s, sizeof *s) == 0);
  free(e);

  sf_scene_domain d;
  sf_error_clear(&err);
  CHECK(sf_scene_get_domain(s, &d, &err) == 0);
  /* viewers up to 400 km move to the top of the 100 km atmosphere */
  CHECK_REL(d.h_min_km, 0.0, 0.0);
  CHECK_REL(d.h_max_km, 100.0, 0.0);
  CHECK_REL(d.mu_min, -1.0, 0.0);
  CHECK_REL(d.mu_max, 1.0, 0.0);
  CHECK_REL(d.mu_s_min, -0.17364817766693035, 1e-15); /* sin 10° */
  CHECK_REL(d.mu_s_max, 1.0, 0.0);
  free(s);
}

static void test_domain(void) {
  printf("\n-- domain in table coordinates --\n");
  sf_scene *s = calloc(1, sizeof *s);
  sf_scene_default(s);
  s->view = SF_VIEW_ABOVE_HORIZON;
  s->viewer_altitude_km[0] = 0.0;
  s->viewer_altitude_km[1] = 0.0;
  sf_scene_domain d;
  sf_error err;
  sf_error_clear(&err);
  /* ground only: the horizon is horizontal, mu = 0 exactly */
  CHECK(sf_scene_get_domain(s, &d, &err) == 0);
  CHECK_ABS(d.mu_min, 0.0, 0.0);
  CHECK_REL(d.h_max_km, 0.0, 0.0);
  /* 0..15 km: the 15 km viewer's horizon -sqrt(1 - (R/(R+h))^2) = -sqrt(h(2R+h))/(R+h) */
  s->viewer_altitude_km[1] = 15.0;
  CHECK(sf_scene_get_domain(s, &d, &err) == 0);
  CHECK_REL(d.h_min_km, 0.0, 0.0);
  CHECK_REL(d.h_max_km, 15.0, 0.0);
  CHECK_REL(d.mu_min, -sqrt(15.0 * (2.0 * 6360.0 + 15.0)) / 6375.0, 1e-14);
  CHECK_REL(d.mu_max, 1.0, 0.0);
  CHECK_REL(d.mu_s_min, -0.17364817766693035, 1e-15);
  CHECK_REL(d.mu_s_max, 1.0, 0.0);
  /* a space viewer (400 km) is moved to the top (100 km) */
  s->viewer_altitude_km[0] = 120.0;
  s->viewer_altitude_km[1] = 400.0;
  s->sun_elevation_deg[0] = 30.0;
  s->sun_elevation_deg[1] = 45.0;
  CHECK(sf_scene_get_domain(s, &d, &err) == 0);
  CHECK_REL(d.h_min_km, 100.0, 0.0);
  CHECK_REL(d.h_max_km, 100.0, 0.0);
  CHECK_REL(d.mu_min, -sqrt(100.0 * (2.0 * 6360.0 + 100.0)) / 6460.0, 1e-14);
  CHECK_REL(d.mu_s_min, 0.5, 1e-15);
  CHECK_REL(d.mu_s_max, sqrt(0.5), 1e-15);
  /* viewers all at or above the top use the rays entering it there, going
   * down: mu up to 0 (rays up leave at once; sampled, they had diluted a
   * space scene's errors with zeros); with a viewer inside, up to 1 */
  CHECK_ABS(d.mu_max, 0.0, 0.0);
  s->viewer_altitude_km[0] = 100.0;
  CHECK(sf_scene_get_domain(s, &d, &err) == 0);
  CHECK_ABS(d.mu_max, 0.0, 0.0);
  s->viewer_altitude_km[0] = 99.0;
  CHECK(sf_scene_get_domain(s, &d, &err) == 0);
  CHECK_REL(d.mu_max, 1.0, 0.0);
  /* empty domains of hand-built scenes */
  sf_scene_domain before;
  memset(&before, 0x5a, sizeof before);
  s->viewer_altitude_km[0] = 20.0;
  s->viewer_altitude_km[1] = 10.0;
  d = before;
  sf_error_clear(&err);
  int rc = sf_scene_get_domain(s, &d, &err);
  printf("viewer 20..10: rc=%d %s\n", rc, err.message);
  CHECK(rc == SF_ERR_INPUT && strstr(err.message, "viewer_altitude_km") && strstr(err.message, "empty"));
  CHECK(memcmp(&d, &before, sizeof d) == 0);
  s->viewer_altitude_km[0] = 0.0;
  s->sun_elevation_deg[0] = 50.0;
  sf_error_clear(&err);
  rc = sf_scene_get_domain(s, &d, &err);
  printf("sun 50..45: rc=%d %s\n", rc, err.message);
  CHECK(rc == SF_ERR_INPUT && strstr(err.message, "sun_elevation_deg") && strstr(err.message, "empty"));
  CHECK(memcmp(&d, &before, sizeof d) == 0);
  free(s);
}

/* A rejected scene must give SF_ERR_INPUT, a one-line message
 * "bad.json: <path>: <problem containing word>", and leave *out untouched. */
static void expect_error(const char *label, const char *single_quoted, const char *want_path,
                         const char *want_word) {
  char *text = json_q(single_quoted);
  sf_scene *out = malloc(sizeof *out), *before = malloc(sizeof *before);
  memset(out, 0x5a, sizeof *out);
  memcpy(before, out, sizeof *out);
  sf_error err;
  sf_error_clear(&err);
  int rc = sf_scene_load_string(text, "bad.json", tmp_dir, out, &err);
  printf("%-30s rc=%d %s\n", label, rc, err.message);
  char want_prefix[400];
  snprintf(want_prefix, sizeof want_prefix, "bad.json: %s: ", want_path);
  int ok = rc == SF_ERR_INPUT && err.status == SF_ERR_INPUT &&
           strncmp(err.message, want_prefix, strlen(want_prefix)) == 0 &&
           strstr(err.message + strlen(want_prefix), want_word) != NULL &&
           strchr(err.message, '\n') == NULL && memcmp(out, before, sizeof *out) == 0;
  if (!ok) printf("     wanted prefix \"%s\" and the word \"%s\"\n", want_prefix, want_word);
  check_report(ok, label, __FILE__, __LINE__);
  free(text);
  free(out);
  free(before);
}

static void test_invalid(void) {
  printf("\n-- rejected scene files --\n");
  expect_error("syntax error", "{\n  'view': 'all',\n  'color' 'rgb'\n}", "line 3, column 11", "syntax");
  expect_error("syntax: end of input", "{'view': 'all',", "line 1, column 16", "end of input");
  expect_error("root not an object", "[1, 2]", "(root)", "object");
  expect_error("unknown key", "{'viewer_altitude': [0, 1]}", "viewer_altitude", "unknown key");
  expect_error("duplicate key", "{'view': 'all', 'view': 'all'}", "view", "duplicate");
  expect_error("name wrong type", "{'name': 7}", "name", "string");
  expect_error("atmosphere wrong type", "{'atmosphere': {'base': 'default'}}", "atmosphere", "string");

  char missing[600];
  snprintf(missing, sizeof missing, "cannot open atmosphere file \"%s/no_such.json\"", tmp_dir);
  expect_error("atmosphere missing", "{'atmosphere': 'no_such.json'}", "atmosphere", missing);
  write_file("flat.json", "{'base': 'default', 'top_radius_km': 6000}");
  char inner[600];
  snprintf(inner, sizeof inner, "%s/flat.json: top_radius_km: must be greater", tmp_dir);
  expect_error("atmosphere invalid", "{'atmosphere': 'flat.json'}", "atmosphere", inner);

  expect_error("viewer not an array", "{'viewer_altitude_km': 10}", "viewer_altitude_km", "[min, max]");
  expect_error("viewer 3 values", "{'viewer_altitude_km': [0, 1, 2]}", "viewer_altitude_km", "got 3 values");
  expect_error("viewer not a number", "{'viewer_altitude_km': [0, '15']}", "viewer_altitude_km[1]", "number");
  expect_error("viewer not finite", "{'viewer_altitude_km': [0, 1e999]}", "viewer_altitude_km[1]", "finite");
  expect_error("viewer negative", "{'viewer_altitude_km': [-1, 15]}", "viewer_altitude_km[0]", ">= 0");
  expect_error("viewer min > max", "{'viewer_altitude_km': [20, 15]}", "viewer_altitude_km", "empty domain");
  expect_error("sun above 90", "{'sun_elevation_deg': [0, 95]}", "sun_elevation_deg[1]", "[-90, 90]");
  expect_error("sun below -90", "{'sun_elevation_deg': [-91, 0]}", "sun_elevation_deg[0]", "[-90, 90]");
  expect_error("sun min > max", "{'sun_elevation_deg': [10, 5]}", "sun_elevation_deg", "empty domain");
  expect_error("view unknown", "{'view': 'below_horizon'}", "view", "known: all, above_horizon");
  expect_error("view wrong type", "{'view': true}", "view", "string");
  expect_error("quantities empty", "{'quantities': []}", "quantities", "empty");
  expect_error("quantities unknown", "{'quantities': ['transmittance', 'irradiance']}", "quantities[1]",
               "known: sky_radiance, transmittance");
  expect_error("quantities twice", "{'quantities': ['transmittance', 'transmittance']}", "quantities[1]",
               "twice");
  expect_error("quantities not array", "{'quantities': 'transmittance'}", "quantities", "array");
  expect_error("color unknown", "{'color': 'spectral3'}", "color", "known: rgb, spectral4");
  expect_error("budget zero", "{'error_budget': {'transmittance_rmse': 0}}", "error_budget.transmittance_rmse",
               "> 0");
  expect_error("budget negative", "{'error_budget': {'sky_radiance_rel_rmse': -0.1}}",
               "error_budget.sky_radiance_rel_rmse", "> 0");
  expect_error("budget not finite", "{'error_budget': {'transmittance_rmse': -1e999}}",
               "error_budget.transmittance_rmse", "finite");
  expect_error("budget unknown key", "{'error_budget': {'rmse': 1}}", "error_budget.rmse", "unknown key");
  expect_error("budget wrong type", "{'error_budget': 0.1}", "error_budget", "object");
  expect_error("outputs unknown key", "{'outputs': {'glsl': 'a.glsl', 'hlsl': 'a.hlsl'}}", "outputs.hlsl",
               "unknown key");
  expect_error("outputs empty path", "{'outputs': {'c': ''}}", "outputs.c", "empty");

  /* an impossible but positive budget is valid: the build reports it later */
  sf_scene *s = calloc(1, sizeof *s);
  sf_error err;
  sf_error_clear(&err);
  char *text = json_q("{'error_budget': {'transmittance_rmse': 1e-30}, 'color': 'spectral4'}");
  int rc = sf_scene_load_string(text, "tiny.json", NULL, s, &err);
  printf("tiny budget: rc=%d %s\n", rc, rc ? err.message : "(loaded)");
  CHECK(rc == 0);
  CHECK_REL(s->transmittance_rmse_budget, 1e-30, 0.0);
  CHECK_REL(s->sky_radiance_rel_rmse_budget, 0.05, 0.0);
  CHECK(s->color == SF_COLOR_SPECTRAL4);
  free(text);
  /* a scene file that does not exist */
  sf_error_clear(&err);
  rc = sf_scene_load_file("/nonexistent/scene.json", s, &err);
  printf("missing scene: rc=%d %s\n", rc, err.message);
  CHECK(rc == SF_ERR_INPUT && strstr(err.message, "/nonexistent/scene.json") == err.message);
  free(s);
}

int main(void) {
  const char *tmp = getenv("TMPDIR");
  snprintf(tmp_dir, sizeof tmp_dir, "%s/skyfit_scene_XXXXXX", tmp && *tmp ? tmp : "/tmp");
  if (!mkdtemp(tmp_dir)) {
    perror("mkdtemp");
    return 1;
  }
  test_spec_example();
  test_relative_paths();
  test_default_scene();
  test_domain();
  test_invalid();
  /* clean up the files this test wrote */
  static const char *const files[] = {"earth.json", "flight.json", "thin.json", "flat.json",
                                      "scenes/ground.json"};
  for (size_t i = 0; i < sizeof files / sizeof files[0]; ++i) {
    char p[512];
    snprintf(p, sizeof p, "%s/%s", tmp_dir, files[i]);
    remove(p);
  }
  char p[512];
  snprintf(p, sizeof p, "%s/scenes", tmp_dir);
  rmdir(p);
  rmdir(tmp_dir);
  return check_summary();
}
