/* The naive sky (models/sky_naive.h), the report's sky-radiance baseline:
 *   - with many steps it converges to the reference single scattering
 *     (models/single_scattering.h, an adaptive quadrature with exact
 *     transmittances) times the phase functions, summed over constituents,
 *     on ground, airborne, top and space viewers, toward the ground and
 *     with the sun below the horizon (the planet's shadow on the ray);
 *   - its float32 evaluation (what the report times) and its emitted C
 *     (codegen/emit_sky_naive.h, compiled here through the build's stable
 *     name skyfit_sky_radiance) agree with its double one;
 *   - a viewer far outside sees what a viewer where its ray enters sees;
 *   - the candidate the build measures is that model. */
#include <dlfcn.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include "check.h"
#include "emitted_library.h"
#include "codegen/codegen_file.h"
#include "codegen/emit_selection_alias.h"
#include "fit/candidate_builtin.h"
#include "models/atmosphere_file.h"
#include "models/phase.h"
#include "models/single_scattering.h"
#include "models/sky_naive.h"
#include "models/view_ray.h"

typedef void (*sky_fn)(float h, float mu, float mu_s, float nu, float *out);

enum { N_POINTS = 11 };
static const double points[N_POINTS][4] = {
    {0.0, 0.3, 0.5, 0.2},      /* ground, noon-ish */
    {0.0, 0.02, 0.05, 0.9},    /* horizon, toward a low sun */
    {0.0, 0.6, -0.05, 0.1},    /* sun just below the horizon: the shadow on the ray */
    {5.0, -0.4, 0.8, -0.2},    /* from a plane toward the ground */
    {5.0, -0.05, 0.1, 0.95},   /* near the horizon from a plane, the sun ahead */
    {40.0, 0.1, -0.08, 0.3},   /* high, the sun below the ground's horizon, not this viewer's */
    {100.0, -0.3, 0.4, 0.0},   /* at the top, looking down */
    {1000.0, -0.99, 0.5, -0.4},/* space */
    {20.0, 0.9, 1.0, 0.9},     /* sun overhead */
    /* 1 and 1.7 m up, looking down: the float32 evaluation had taken
     * radii's differences there, 2.3 % and 11 % off the emitted code */
    {0.001, -0.5, 0.5, 0.0},
    {0.00165561, -0.6595, 0.5771, -0.1962},
};

/* The reference: sum_i P_i(nu) times single scattering of constituent i. */
static void reference(const sf_atmosphere *atm, const double *p, double *L) {
  double nu = sf_clamp_nu(p[1], p[2], p[3]), mu_s_e, single[SF_MAX_CONSTITUENTS * SF_MAX_CHANNELS];
  sf_view_ray ray;
  const char *why = NULL;
  for (int k = 0; k < atm->n_channels; ++k) L[k] = 0.0;
  if (sf_view_ray_make_at_entry(atm, p[0], p[1], p[2], nu, SF_RAY_END_NEAREST, -1.0, &ray, &mu_s_e, &why) != 0) return;
  sf_single_scattering(atm, &ray, mu_s_e, nu, single);
  for (int i = 0; i < atm->n_constituents; ++i)
    for (int k = 0; k < atm->n_channels; ++k)
      L[k] += sf_phase_value(&atm->constituents[i].phase, nu) * single[i * atm->n_channels + k];
}

static double worst_rel(const double *a, const double *b, int n) {
  double scale = 0.0, worst = 0.0;
  for (int k = 0; k < n; ++k) scale = fmax(scale, fabs(b[k]));
  for (int k = 0; k < n; ++k) worst = fmax(worst, fabs(a[k] - b[k]) / fmax(scale, 1e-30));
  return worst;
}

static void check_convergence(const sf_atmosphere *atm) {
  sf_sky_naive fine = {atm, 4096, 1024}, coarse = {atm, SF_SKY_NAIVE_VIEW_STEPS, SF_SKY_NAIVE_SUN_STEPS};
  double worst_fine = 0.0, worst_coarse = 0.0;
  for (int p = 0; p < N_POINTS; ++p) {
    double want[4], got[4], got_coarse[4];
    reference(atm, points[p], want);
    sf_sky_naive_radiance(&fine, points[p][0], points[p][1], points[p][2], points[p][3], got);
    sf_sky_naive_radiance(&coarse, points[p][0], points[p][1], points[p][2], points[p][3], got_coarse);
    double e = worst_rel(got, want, atm->n_channels), ec = worst_rel(got_coarse, want, atm->n_channels);
    printf("point %d: reference %.6g %.6g %.6g; 4096 x 1024 steps rel %.2e; 16 x 8 steps rel %.2e\n", p, want[0],
           want[1], want[2], e, ec);
    CHECK(want[2] > 0.0);
    worst_fine = fmax(worst_fine, e);
    worst_coarse = fmax(worst_coarse, ec);
  }
  /* midpoint sums: O(step^2) where the integrand is smooth, O(step) at the
   * shadow's edge on the ray */
  printf("converged: worst %.3g (bound 2e-3); the default 16 x 8: worst %.3g\n", worst_fine, worst_coarse);
  CHECK(worst_fine <= 2e-3);
  CHECK(worst_coarse > worst_fine);   /* the steps matter: the coarse sums are not the converged ones */
}

static int build_library(const char *dir, const char *header, const char *so) {
  char driver[1200], text[2048];
  snprintf(driver, sizeof driver, "%s/driver.c", dir);
  snprintf(text, sizeof text,
           "#include \"%s\"\n"
           "void eval_sky(float h, float mu, float mu_s, float nu, float *out) {\n"
           "  skyfit_vec3 v = skyfit_sky_radiance(h, mu, mu_s, nu);\n"
           "  out[0] = v.x; out[1] = v.y; out[2] = v.z;\n"
           "}\n",
           header);
  return emitted_library_build(driver, text, so);
}

static void check_emitted(const sf_atmosphere *atm, const char *dir, const char *base) {
  sf_candidate c;
  sf_error err = {0};
  if (!CHECK(sf_candidate_sky_naive(atm, &c, &err) == SF_OK)) return;
  CHECK(c.quantity == SF_CANDIDATE_SKY_RADIANCE && c.role == SF_ROLE_BASELINE && c.emit && c.eval_f32);
  sf_scene_domain domain;
  memset(&domain, 0, sizeof domain);
  domain.h_min_km = 0.0;
  domain.h_max_km = 1000.0;
  domain.mu_min = domain.mu_s_min = -1.0;
  domain.mu_max = domain.mu_s_max = 1.0;
  sf_selection_alias alias;
  memset(&alias, 0, sizeof alias);
  alias.n_channels = atm->n_channels;
  snprintf(alias.sky_radiance, sizeof alias.sky_radiance, "%s", c.emit_name);
  alias.sky_takes_altitude = !c.emit_ground_viewer;
  sf_codegen_part parts[2];
  memset(parts, 0, sizeof parts);
  snprintf(parts[0].name, sizeof parts[0].name, "%s", c.emit_name);
  snprintf(parts[0].quantity, sizeof parts[0].quantity, "sky_radiance");
  parts[0].domain = domain;
  parts[0].emit = c.emit;
  parts[0].model = c.emit_model;
  snprintf(parts[1].name, sizeof parts[1].name, "selection");
  snprintf(parts[1].quantity, sizeof parts[1].quantity, "stable names");
  parts[1].domain = domain;
  parts[1].emit = sf_emit_selection_alias;
  parts[1].model = &alias;
  char header[1200], so[1200];
  printf("-- %s\n", atm->name);
  snprintf(header, sizeof header, "%s/%s.h", dir, base);
  snprintf(so, sizeof so, "%s/%s.so", dir, base);
  if (!CHECK(sf_codegen_write(parts, 2, 1, 1, dir, base, NULL, &err) == SF_OK)) {
    printf("%s\n", err.message);
    sf_candidate_free(&c);
    return;
  }
  void *lib = NULL;
  sky_fn eval = NULL;
  if (CHECK(build_library(dir, header, so) == 0) && CHECK((lib = dlopen(so, RTLD_NOW | RTLD_LOCAL)) != NULL))
    *(void **)&eval = dlsym(lib, "eval_sky");
  double worst_emitted = 0.0, worst_f32 = 0.0;
  for (int p = 0; eval && p < N_POINTS; ++p) {
    double want[4];
    float emitted[3], f32[3], in[4] = {(float)points[p][0], (float)points[p][1], (float)points[p][2],
                                       (float)points[p][3]};
    c.eval(c.ctx, points[p], want);
    eval(in[0], in[1], in[2], in[3], emitted);
    c.eval_f32(c.ctx, 1, in, f32);
    double e[3], f[3];
    for (int k = 0; k < 3; ++k) e[k] = emitted[k], f[k] = f32[k];
    worst_emitted = fmax(worst_emitted, worst_rel(e, want, 3));
    worst_f32 = fmax(worst_f32, worst_rel(f, want, 3));
  }
  /* float32 roundings of the sums (the inputs' own rounding included: a
   * float mu near the horizon moves the ray) */
  printf("emitted C vs the double: worst rel %.3g; float32 evaluation vs the double: %.3g (bounds 1e-4)\n",
         worst_emitted, worst_f32);
  CHECK(worst_emitted <= 1e-4);
  CHECK(worst_f32 <= 1e-4);
  /* far viewers straight down and onto a ray 30 km above the ground at its
   * closest: the values at the ray's entry */
  const double R = atm->bottom_radius_km, top = atm->top_radius_km;
  double worst_far = 0.0, worst_far_emitted = 0.0;
  for (int a = 0; eval && a < 2; ++a) {
    double closest = a ? R + 30.0 : 0.0, mu_e = -sqrt((1.0 - closest / top) * (1.0 + closest / top));
    const double mu_s = 0.6;
    for (int f = 0; f < 3; ++f) {
      double far = f == 0 ? 1000.0 : (f == 1 ? 1e4 : 1e6), r = R + far;
      double mu = -sqrt((1.0 - closest / r) * (1.0 + closest / r));
      /* a sun 2 rad round the view direction from the plane of the view and the zenith */
      double nu = sf_clamp_nu(mu, mu_s, mu * mu_s + sqrt((1.0 - mu * mu) * (1.0 - mu_s * mu_s)) * cos(2.0));
      double got[4], at_entry[4];
      /* the sun's cosine at the entry point, for the same sun direction */
      sf_view_ray ray;
      double mu_s_e;
      const char *why = NULL;
      if (!CHECK(sf_view_ray_make_at_entry(atm, far, mu, mu_s, nu, SF_RAY_END_NEAREST, -1.0, &ray, &mu_s_e, &why) ==
                 0))
        continue;
      c.eval(c.ctx, (const double[4]){top - R, mu_e, mu_s_e, nu}, at_entry);
      c.eval(c.ctx, (const double[4]){far, mu, mu_s, nu}, got);
      float emitted[3];
      eval((float)far, (float)mu, (float)mu_s, (float)nu, emitted);
      double e[3] = {emitted[0], emitted[1], emitted[2]};
      worst_far = fmax(worst_far, worst_rel(got, at_entry, 3));
      worst_far_emitted = fmax(worst_far_emitted, worst_rel(e, at_entry, 3));
    }
  }
  printf("viewers 1000 km to 1e6 km out vs at the entry point: double %.3g (bound 1e-6), emitted C %.3g (bound "
         "1e-3)\n", worst_far, worst_far_emitted);
  CHECK(worst_far <= 1e-6);
  CHECK(worst_far_emitted <= 1e-3);
  /* the GLSL compiles, where glslangValidator is installed (scripts/setup.sh) */
  char cmd[4096];
  snprintf(cmd, sizeof cmd,
           "command -v glslangValidator >/dev/null || exit 77; { echo '#version 330'; cat %s/%s.glsl; "
           "echo 'out vec4 c; void main() { c = vec4(skyfit_sky_radiance(1.0, 0.3, 0.5, 0.2), 1.0); }'; } "
           "> %s/use.frag && glslangValidator %s/use.frag > %s/glsl.log",
           dir, base, dir, dir, dir);
  int rc = system(cmd);
  if (WIFEXITED(rc) && WEXITSTATUS(rc) == 77) printf("glslangValidator not installed: GLSL not compiled\n");
  else if (CHECK(rc == 0)) printf("the GLSL compiles (glslangValidator)\n");
  if (lib) dlclose(lib);
  sf_candidate_free(&c);
}

int main(void) {
  sf_atmosphere atm;
  sf_atmosphere_default(&atm);
  check_convergence(&atm);
  char dir[] = "/tmp/skyfit-sky-naive-XXXXXX";
  if (!mkdtemp(dir)) return 1;
  check_emitted(&atm, dir, "naive_sky");
  /* and with a constituent that absorbs only (but names a phase function)
   * and one that does nothing: their unread variables had failed -Wall
   * -Werror (the phase function, the depths) */
  sf_atmosphere odd = atm;
  snprintf(odd.name, sizeof odd.name, "default with an absorber and a transparent constituent");
  sf_constituent *absorber = &odd.constituents[odd.n_constituents++];
  *absorber = atm.constituents[1];
  snprintf(absorber->name, sizeof absorber->name, "soot");
  for (int k = 0; k < odd.n_channels; ++k) absorber->scattering[k] = 0.0, absorber->absorption[k] = 2e-4 * (k + 1);
  sf_constituent *none = &odd.constituents[odd.n_constituents++];
  *none = atm.constituents[0];
  snprintf(none->name, sizeof none->name, "nothing");
  for (int k = 0; k < odd.n_channels; ++k) none->scattering[k] = none->absorption[k] = 0.0;
  sf_atmosphere_finalize(&odd);
  check_emitted(&odd, dir, "naive_sky_odd");
  char cmd[200];
  snprintf(cmd, sizeof cmd, "rm -rf %s", dir);
  if (system(cmd) != 0) printf("could not remove %s\n", dir);
  return check_summary();
}
