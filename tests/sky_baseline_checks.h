/* What the tests of the single-scattering sky baselines share
 * (tests/test_sky_naive.c, test_sky_raymarched.c): the reference they
 * converge to, seed 000 eq. 59's shell chord, the error measure, the
 * candidate's header written and
 * compiled as the build writes it (with the stable name
 * skyfit_sky_radiance), its GLSL compiled, and the far viewers whose
 * values must be those at their ray's entry. */
#ifndef SKYFIT_TESTS_SKY_BASELINE_CHECKS_H
#define SKYFIT_TESTS_SKY_BASELINE_CHECKS_H

#include <dlfcn.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>

#include "check.h"
#include "emitted_library.h"
#include "codegen/codegen_file.h"
#include "codegen/emit_selection_alias.h"
#include "fit/candidate.h"
#include "models/phase.h"
#include "models/single_scattering.h"
#include "models/view_ray.h"

/* The points (h_km, mu, mu_s, nu) the skies are checked at. */
enum { SKY_POINTS = 12 };
static const double sky_points[SKY_POINTS][4] = {
    {0.0, 0.3, 0.5, 0.2},       /* ground, noon-ish */
    {0.0, 0.02, 0.05, 0.9},     /* horizon, toward a low sun */
    {0.0, 0.6, -0.05, 0.1},     /* sun just below the horizon: the shadow on the ray */
    {5.0, -0.4, 0.8, -0.2},     /* from a plane toward the ground */
    {5.0, -0.05, 0.1, 0.95},    /* near the horizon from a plane, the sun ahead */
    {40.0, 0.1, -0.08, 0.3},    /* high, the sun below the ground's horizon, not this viewer's */
    {100.0, -0.3, 0.4, 0.0},    /* at the top, looking down */
    {1000.0, -0.99, 0.5, -0.4}, /* space */
    {20.0, 0.9, 1.0, 0.9},      /* sun overhead */
    /* 1 and 1.7 m up, looking down: the naive sky's float32 evaluation had
     * taken radii's differences there, 2.3 % and 11 % off the emitted code */
    {0.001, -0.5, 0.5, 0.0},
    {0.00165561, -0.6595, 0.5771, -0.1962},
    {60.0, -0.1, -0.2, 0.9},    /* from the planet's shadow out into the light */
};

/* The reference at p = (h, mu, mu_s, nu): sum_i P_i(nu) times the single
 * scattering of constituent i (models/single_scattering.h) to rel_tol. */
static inline void sky_reference(const sf_atmosphere *atm, const double *p, double rel_tol, double *L) {
  double nu = sf_clamp_nu(p[1], p[2], p[3]), mu_s_e, single[SF_MAX_CONSTITUENTS * SF_MAX_CHANNELS];
  sf_view_ray ray;
  const char *why = NULL;
  for (int k = 0; k < atm->n_channels; ++k) L[k] = 0.0;
  if (sf_view_ray_make_at_entry(atm, p[0], p[1], p[2], nu, SF_RAY_END_NEAREST, -1.0, &ray, &mu_s_e, &why) != 0) return;
  sf_single_scattering_tol(atm, &ray, mu_s_e, nu, rel_tol, single);
  for (int i = 0; i < atm->n_constituents; ++i)
    for (int k = 0; k < atm->n_channels; ++k)
      L[k] += sf_phase_value(&atm->constituents[i].phase, nu) * single[i * atm->n_channels + k];
}

/* Where the upward ray from altitude h along the zenith cosine c leaves the
 * top of atm: the distance, and the cosine there in *c_top. */
static inline double sky_top_exit(const sf_atmosphere *atm, double h, double c, double *c_top) {
  double r = atm->bottom_radius_km + h, top = atm->top_radius_km;
  double t = -r * c + sqrt(r * r * c * c + top * top - r * r);
  *c_top = (r * c + t) / top;
  return t;
}

/* The length of [0, t_end] along the line from radius r at zenith cosine c
 * inside the sphere of radius rho. */
static inline double sky_inside_sphere(double r, double c, double rho, double t_end) {
  double disc = r * r * c * c - r * r + rho * rho;
  if (disc <= 0.0) return 0.0;
  double a = fmax(-r * c - sqrt(disc), 0.0), b = fmin(-r * c + sqrt(disc), t_end);
  return b > a ? b - a : 0.0;
}

/* seed 000 eq. 59: the length of [0, t_end] along that line inside the
 * shell lo..hi (km above the ground R): inside its top sphere, less inside
 * its bottom one. */
static inline double sky_eq59_chord(double R, double lo, double hi, double r, double c, double t_end) {
  return sky_inside_sphere(r, c, R + hi, t_end) - sky_inside_sphere(r, c, R + lo, t_end);
}

/* The largest |a - b| over the channels, relative to b's largest channel. */
static inline double sky_worst_rel(const double *a, const double *b, int n) {
  double scale = 0.0, worst = 0.0;
  for (int k = 0; k < n; ++k) scale = fmax(scale, fabs(b[k]));
  for (int k = 0; k < n; ++k) worst = fmax(worst, fabs(a[k] - b[k]) / fmax(scale, 1e-30));
  return worst;
}

typedef void (*sky_fn)(float h, float mu, float mu_s, float nu, float *out);

/* Writes dir/base.h and .glsl for candidate c (a 3-channel sky) with the
 * build's stable names, compiles the C into dir/base.so with -Werror and
 * loads it: *lib and *eval (eval_sky(h, mu, mu_s, nu, out[3])). 0, or -1. */
static inline int sky_emitted_load(const sf_candidate *c, const sf_atmosphere *atm, const char *dir, const char *base,
                                   void **lib, sky_fn *eval) {
  sf_scene_domain domain;
  memset(&domain, 0, sizeof domain);
  domain.h_max_km = 1000.0;
  domain.mu_min = domain.mu_s_min = -1.0;
  domain.mu_max = domain.mu_s_max = 1.0;
  sf_selection_alias alias;
  memset(&alias, 0, sizeof alias);
  alias.n_channels = atm->n_channels;
  snprintf(alias.sky_radiance, sizeof alias.sky_radiance, "%s", c->emit_name);
  alias.sky_takes_altitude = !c->emit_ground_viewer;
  sf_codegen_part parts[2];
  memset(parts, 0, sizeof parts);
  snprintf(parts[0].name, sizeof parts[0].name, "%s", c->emit_name);
  snprintf(parts[0].quantity, sizeof parts[0].quantity, "sky_radiance");
  parts[0].domain = domain;
  parts[0].emit = c->emit;
  parts[0].model = c->emit_model;
  snprintf(parts[1].name, sizeof parts[1].name, "selection");
  snprintf(parts[1].quantity, sizeof parts[1].quantity, "stable names");
  parts[1].domain = domain;
  parts[1].emit = sf_emit_selection_alias;
  parts[1].model = &alias;
  sf_error err = {0};
  if (sf_codegen_write(parts, 2, 1, 1, dir, base, NULL, &err) != SF_OK) {
    printf("%s\n", err.message);
    return -1;
  }
  char driver[1200], so[1200], text[2048];
  snprintf(driver, sizeof driver, "%s/%s_driver.c", dir, base);
  snprintf(so, sizeof so, "%s/%s.so", dir, base);
  snprintf(text, sizeof text,
           "#include \"%s/%s.h\"\n"
           "void eval_sky(float h, float mu, float mu_s, float nu, float *out);\n"
           "void eval_sky(float h, float mu, float mu_s, float nu, float *out) {\n"
           "  skyfit_vec3 v = skyfit_sky_radiance(h, mu, mu_s, nu);\n"
           "  out[0] = v.x; out[1] = v.y; out[2] = v.z;\n"
           "}\n",
           dir, base);
  if (emitted_library_build(driver, text, so) != 0 || !(*lib = dlopen(so, RTLD_NOW | RTLD_LOCAL))) return -1;
  *(void **)eval = dlsym(*lib, "eval_sky");
  return *eval ? 0 : -1;
}

/* dir/base.glsl with a main calling skyfit_sky_radiance through
 * glslangValidator, where it is installed (scripts/setup.sh). */
static inline void sky_check_glsl(const char *dir, const char *base) {
  char cmd[4096];
  snprintf(cmd, sizeof cmd,
           "command -v glslangValidator >/dev/null || exit 77; { echo '#version 330'; cat %s/%s.glsl; "
           "echo 'out vec4 c; void main() { c = vec4(skyfit_sky_radiance(1.0, 0.3, 0.5, 0.2), 1.0); }'; } "
           "> %s/use.frag && glslangValidator %s/use.frag > %s/glsl.log",
           dir, base, dir, dir, dir);
  int rc = system(cmd);
  if (WIFEXITED(rc) && WEXITSTATUS(rc) == 77) printf("glslangValidator not installed: GLSL not compiled\n");
  else if (CHECK(rc == 0)) printf("the GLSL compiles (glslangValidator)\n");
}

enum { SKY_FAR_VIEWERS = 6 };

/* Viewers 1000, 1e4 and 1e6 km up looking straight down and onto a ray 30
 * km above the ground at its closest, the sun 2 rad round the view
 * direction from the plane of the view and the zenith: far[v] their
 * inputs, entry[v] those of a viewer where the ray enters (the top, its
 * cosines there). Returns how many were made. */
static inline int sky_far_viewers(const sf_atmosphere *atm, double far[SKY_FAR_VIEWERS][4],
                                  double entry[SKY_FAR_VIEWERS][4]) {
  const double R = atm->bottom_radius_km, top = atm->top_radius_km, mu_s = 0.6;
  int n = 0;
  for (int a = 0; a < 2; ++a) {
    double closest = a ? R + 30.0 : 0.0, mu_e = -sqrt((1.0 - closest / top) * (1.0 + closest / top));
    for (int f = 0; f < 3; ++f) {
      double h = f == 0 ? 1000.0 : (f == 1 ? 1e4 : 1e6), r = R + h;
      double mu = -sqrt((1.0 - closest / r) * (1.0 + closest / r));
      double nu = sf_clamp_nu(mu, mu_s, mu * mu_s + sqrt((1.0 - mu * mu) * (1.0 - mu_s * mu_s)) * cos(2.0));
      sf_view_ray ray;
      double mu_s_e;
      const char *why = NULL;
      if (!CHECK(sf_view_ray_make_at_entry(atm, h, mu, mu_s, nu, SF_RAY_END_NEAREST, -1.0, &ray, &mu_s_e, &why) == 0))
        continue;
      double in[4] = {h, mu, mu_s, nu}, at[4] = {top - R, mu_e, mu_s_e, nu};
      memcpy(far[n], in, sizeof in);
      memcpy(entry[n], at, sizeof at);
      ++n;
    }
  }
  return n;
}

#endif
