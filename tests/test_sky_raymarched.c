/* Leenman's raymarched sky (models/sky_raymarched.h):
 *   - the piece integral (e^-a - e^-b) / (b - a) against its closed form,
 *     also where a and b meet;
 *   - with the reference's optical depths and many steps the integrator
 *     converges to the reference single scattering (models/single_scattering.h,
 *     an adaptive quadrature) times the phase functions, on ground,
 *     airborne, top and space viewers, toward the ground and across the
 *     planet's shadow; at second order, the shadow's edges included;
 *   - with the flat model's depths it is exact where the flat model is:
 *     looking straight up with the sun overhead, whatever the steps;
 *   - in one step (Leenman's flat sky) looking up it is seed 000 eq. 52,
 *     transcribed here with eq. 51's columns and eq. 59's shell;
 *   - it does not jump where the planet's shadow appears on a ray;
 *   - a viewer far outside sees what a viewer where its ray enters sees;
 *   - the candidates the build measures (raymarched-sky, flat-sky) are
 *     that model, and their emitted C
 *     (codegen/emit_sky_raymarched.h, compiled here through the build's
 *     stable name skyfit_sky_radiance) and their float32 evaluation (what
 *     the report times) agree with it, the emitted C also for far viewers;
 *     the GLSL compiles; an atmosphere with an absorber and one with no
 *     exponential constituent compile with -Wall -Wextra -Werror, one
 *     with 5 constituents is not emitted (its columns travel in a vec4). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "sky_baseline_checks.h"
#include "fit/candidate_builtin.h"
#include "models/atmosphere_file.h"
#include "models/sky_raymarched.h"

static void check_exp_mean(void) {
  /* (e^-a - e^-b) / (b - a) in long double where b - a is not small, the
   * series e^-a (1 - d/2 + d^2/6 - d^3/24) where it is */
  static const double pairs[][2] = {{0.0, 1.0}, {3.0, 0.5}, {0.2, 40.0}, {700.0, 650.0}, {1.0, 1.0},
                                    {2.0, 2.0 + 1e-9}, {5.0 + 3e-7, 5.0}, {0.0, 1e-300}};
  double worst = 0.0;
  for (size_t p = 0; p < sizeof pairs / sizeof pairs[0]; ++p) {
    double a = pairs[p][0], b = pairs[p][1], d = fabs(b - a), want;
    if (d > 1e-3) want = (double)((expl(-(long double)a) - expl(-(long double)b)) / ((long double)b - a));
    else want = exp(-fmin(a, b)) * (1.0 - d / 2.0 + d * d / 6.0 - d * d * d / 24.0);
    double got = sf_exp_mean_between(a, b);
    worst = fmax(worst, fabs(got - want) / want);
  }
  printf("(e^-a - e^-b) / (b - a): worst rel %.2e (bound 4e-16)\n", worst);
  CHECK(worst <= 4e-16);
}

/* seed 000 eq. 51: the column (km) of d0 exp(-h/H) from altitude h along
 * the zenith cosine c >= 0, through the homogeneous sphere one scale height
 * above the point. */
static double eq51_column(double R, double H, double d0, double h, double c) {
  double r = R + h;
  return d0 * exp(-h / H) * (sqrt((r + H) * (r + H) - r * r + r * r * c * c) - r * c);
}

/* The column of every constituent from (h, c) up to infinity: eq. 51 or 59. */
static void seed_columns(const sf_atmosphere *atm, double h, double c, double *col) {
  double R = atm->bottom_radius_km;
  for (int i = 0; i < atm->n_constituents; ++i) {
    double H, d0, lo, hi;
    if (sf_constituent_exponential(&atm->constituents[i], &H, &d0)) {
      col[i] = eq51_column(R, H, d0, h, c);
    } else {
      sf_flat_shell_of(atm, i, &lo, &hi);
      col[i] = sky_eq59_chord(R, lo, hi, R + h, c, INFINITY);
    }
  }
}

/* eq. 52, summed over constituents: E sum_i beta_s,i P_i col_i times the
 * mean of e^-x between the sun's depth at the viewer and the view ray's
 * (the sun's at the ray's end, on the top, is 0). With to_top set the
 * columns end at the top, as the model's do: less eq. 51's column above
 * where the view ray and the sun ray leave it. */
static void seed_flat_sky(const sf_atmosphere *atm, const double *p, int to_top, double *L) {
  double R = atm->bottom_radius_km, top = atm->top_radius_km - R, h = p[0], mu = p[1], mu_s = p[2], nu = p[3];
  double view[SF_MAX_CONSTITUENTS], sun[SF_MAX_CONSTITUENTS], view_above[SF_MAX_CONSTITUENTS] = {0},
         sun_above[SF_MAX_CONSTITUENTS] = {0};
  seed_columns(atm, h, mu, view);
  seed_columns(atm, h, mu_s, sun);
  if (to_top) {
    double c_view, c_sun;
    sky_top_exit(atm, h, mu, &c_view);
    sky_top_exit(atm, h, mu_s, &c_sun);
    seed_columns(atm, top, c_view, view_above);
    seed_columns(atm, top, c_sun, sun_above);
  }
  for (int k = 0; k < atm->n_channels; ++k) {
    double tau_view = 0.0, tau_light = 0.0, scatter = 0.0;
    for (int i = 0; i < atm->n_constituents; ++i) {
      double col = view[i] - view_above[i];
      tau_view += sf_extinction(atm, i, k) * col;
      tau_light += sf_extinction(atm, i, k) * (sun[i] - sun_above[i]);
      scatter += atm->constituents[i].scattering[k] * sf_phase_value(&atm->constituents[i].phase, nu) * col;
    }
    L[k] = atm->sun_irradiance[k] * scatter * (exp(-tau_view) - exp(-tau_light)) / (tau_light - tau_view);
  }
}

/* Looking up with the sun up, and the sun line's closest approach behind
 * the viewer (mu >= mu_s nu): one piece, the seed's flat sky. */
static void check_flat_is_eq52(const sf_atmosphere *atm) {
  static const double up[][4] = {{0.0, 0.3, 0.5, 0.2}, {0.0, 0.05, 0.1, 0.3}, {0.0, 0.9, 0.7, 0.8},
                                 {5.0, 0.2, 0.02, 0.4}, {20.0, 0.6, 0.3, -0.2}, {50.0, 0.1, 0.9, 0.05}};
  sf_sky_raymarched flat;
  sf_sky_raymarched_make(atm, SF_SKY_FLAT_STEPS, SF_RAYMARCHED_DEPTHS_FLAT, &flat);
  double H_max = 0.0, worst_top = 0.0, worst_seed = 0.0, worst_seed_bound = 0.0;
  for (int i = 0; i < atm->n_constituents; ++i) {
    double H, d0;
    if (sf_constituent_exponential(&atm->constituents[i], &H, &d0)) H_max = fmax(H_max, H);
  }
  for (size_t p = 0; p < sizeof up / sizeof up[0]; ++p) {
    CHECK(up[p][1] >= up[p][2] * up[p][3] && up[p][1] > 0.0 && up[p][2] > 0.0);
    double got[SF_MAX_CHANNELS], to_top[SF_MAX_CHANNELS], seed[SF_MAX_CHANNELS];
    sf_sky_raymarched_radiance(&flat, up[p][0], up[p][1], up[p][2], up[p][3], got);
    seed_flat_sky(atm, up[p], 1, to_top);
    seed_flat_sky(atm, up[p], 0, seed);
    worst_top = fmax(worst_top, sky_worst_rel(got, to_top, atm->n_channels));
    /* eq. 51 to infinity counts the columns above the top too: of the
     * viewer's, about e^-(top - h)/H each, the view's and the sun's */
    double e = sky_worst_rel(got, seed, atm->n_channels);
    double bound = 2.0 * exp(-(atm->top_radius_km - atm->bottom_radius_km - up[p][0]) / H_max);
    CHECK(e <= bound);
    worst_seed = fmax(worst_seed, e);
    worst_seed_bound = fmax(worst_seed_bound, e / bound);
  }
  printf("flat sky looking up vs eq. 52 ended at the top: worst rel %.2e (bound 1e-12); vs eq. 52 to infinity: "
         "%.2e, at most %.2f of 2 e^-(top - h)/H\n", worst_top, worst_seed, worst_seed_bound);
  CHECK(worst_top <= 1e-12);
}

static void check_integrator(const sf_atmosphere *atm) {
  double worst[3] = {0.0, 0.0, 0.0};
  static const int steps[3] = {256, 1024, 4096};
  for (int p = 0; p < SKY_POINTS; ++p) {
    double want[SF_MAX_CHANNELS];
    sky_reference(atm, sky_points[p], 1e-10, want);
    CHECK(want[2] > 0.0);
    for (int s = 0; s < 3; ++s) {
      sf_sky_raymarched m;
      double got[SF_MAX_CHANNELS];
      sf_sky_raymarched_make(atm, steps[s], SF_RAYMARCHED_DEPTHS_EXACT, &m);
      sf_sky_raymarched_radiance(&m, sky_points[p][0], sky_points[p][1], sky_points[p][2], sky_points[p][3], got);
      double e = sky_worst_rel(got, want, atm->n_channels);
      worst[s] = fmax(worst[s], e);
      if (s == 2) printf("point %d: reference %.6g %.6g %.6g; exact depths, 4096 steps: rel %.2e\n", p, want[0],
                         want[1], want[2], e);
    }
  }
  /* the piece integral is exact for a linear optical depth and an even
   * density: its error is second order in the step, edges included (a
   * shadow's edge inside a step would make it first order) */
  printf("exact depths: worst rel %.3g (256 steps), %.3g (1024), %.3g (4096; bound 2e-6); ratios %.1f, %.1f "
         "(second order: 16)\n",
         worst[0], worst[1], worst[2], worst[0] / worst[1], worst[1] / worst[2]);
  CHECK(worst[2] <= 2e-6);
  CHECK(worst[0] / worst[1] > 10.0 && worst[1] / worst[2] > 10.0);
}

/* Looking straight up with the sun overhead the flat model's columns are
 * exact (seed 000 eq. 51 at cos = 1 is the exponential's column; the
 * ozone shell's chord from below is its width, the tent's column; from 40
 * km both are 0), and the depth viewer -> point -> sun is the same at
 * every point: the piece integral is exact too. (From inside the shell its
 * chord is not the tent's column above: 2.5 against 3.33 km at 30 km.) */
static void check_vertical_exact(const sf_atmosphere *atm) {
  double worst = 0.0;
  for (int steps = 1; steps <= SF_SKY_RAYMARCHED_STEPS; steps += 4)
    for (int h = 0; h < 3; ++h) {
      double p[4] = {h == 0 ? 0.0 : (h == 1 ? 5.0 : 40.0), 1.0, 1.0, 1.0}, want[SF_MAX_CHANNELS],
             got[SF_MAX_CHANNELS];
      sf_sky_raymarched m;
      sf_sky_raymarched_make(atm, steps, SF_RAYMARCHED_DEPTHS_FLAT, &m);
      sky_reference(atm, p, 1e-10, want);
      sf_sky_raymarched_radiance(&m, p[0], p[1], p[2], p[3], got);
      worst = fmax(worst, sky_worst_rel(got, want, atm->n_channels));
    }
  printf("flat depths, zenith view and sun, 1 and 5 steps: worst rel %.2e (bound 1e-7)\n", worst);
  CHECK(worst <= 1e-7);
}

static void check_seed_steps(const sf_atmosphere *atm) {
  sf_sky_raymarched seed, fine;
  sf_sky_raymarched_make(atm, SF_SKY_RAYMARCHED_STEPS, SF_RAYMARCHED_DEPTHS_FLAT, &seed);
  sf_sky_raymarched_make(atm, 1024, SF_RAYMARCHED_DEPTHS_FLAT, &fine);
  double worst_seed = 0.0;
  for (int p = 0; p < SKY_POINTS; ++p) {
    double want[SF_MAX_CHANNELS], got[SF_MAX_CHANNELS], got_fine[SF_MAX_CHANNELS];
    sky_reference(atm, sky_points[p], 1e-10, want);
    sf_sky_raymarched_radiance(&seed, sky_points[p][0], sky_points[p][1], sky_points[p][2], sky_points[p][3], got);
    sf_sky_raymarched_radiance(&fine, sky_points[p][0], sky_points[p][1], sky_points[p][2], sky_points[p][3], got_fine);
    for (int k = 0; k < atm->n_channels; ++k) CHECK(isfinite(got[k]) && got[k] >= 0.0);
    double e = sky_worst_rel(got, want, atm->n_channels);
    printf("point %d: flat depths, 5 steps rel %.3g, 1024 steps rel %.3g\n", p, e,
           sky_worst_rel(got_fine, want, atm->n_channels));
    worst_seed = fmax(worst_seed, e);
  }
  printf("flat depths, the seed's 5 steps: worst rel %.3g (its error is the report's)\n", worst_seed);
}

/* As the sun sets the planet's shadow appears on a ray at the point where
 * the sun line passes closest to the ground, and grows: the radiance must
 * not jump there (without a sample at that point it had jumped by 14 %
 * at (10 km, mu -0.05, nu 0.5) between mu_s -0.04686275 and -0.04686100).
 * mu_s is swept across the sunset in steps of 2.5e-6 for viewers on the
 * ground and up to 10 km looking near the horizon, and the step with the
 * largest change is swept again in 64 steps: a jump keeps its whole size
 * there, a continuous change shrinks (to 1/8 where the shadow's edges grow
 * as a square root, to 1/64 where it is smooth). */
static double largest_change(const sf_sky_raymarched *m, const double *view, double mu_s0, double mu_s1, int n,
                             double *at) {
  double biggest = 0.0, prev[SF_MAX_CHANNELS];
  for (int i = 0; i <= n; ++i) {
    double mu_s = mu_s0 + (mu_s1 - mu_s0) * i / n, L[SF_MAX_CHANNELS];
    sf_sky_raymarched_radiance(m, view[0], view[1], mu_s, view[2], L);
    for (int k = 0; k < m->atm->n_channels; ++k) {
      if (i && fabs(L[k] - prev[k]) > biggest) biggest = fabs(L[k] - prev[k]), *at = mu_s;
      prev[k] = L[k];
    }
  }
  return biggest;
}

static void check_shadow_continuity(const sf_atmosphere *atm) {
  static const double views[][3] = {{10.0, -0.05, 0.5}, {2.354, -0.0123, -0.4439}, {0.0, 0.05, 0.3},
                                    {5.0, 0.0, -0.9}};
  sf_sky_raymarched m;
  sf_sky_raymarched_make(atm, SF_SKY_RAYMARCHED_STEPS, SF_RAYMARCHED_DEPTHS_FLAT, &m);
  double worst = 0.0;
  for (size_t v = 0; v < sizeof views / sizeof views[0]; ++v) {
    const double step = 2.5e-6;
    double at = 0.0, at_fine = 0.0;
    double coarse = largest_change(&m, views[v], -0.08, 0.02, 40000, &at);
    double fine = largest_change(&m, views[v], at - step, at, 64, &at_fine);
    printf("view (%g km, mu %g, nu %g): largest change %.3g at mu_s %.8f, %.3g of it in 1/64 of the step\n",
           views[v][0], views[v][1], views[v][2], coarse, at, fine / coarse);
    worst = fmax(worst, fine / coarse);
  }
  printf("sunset sweeps: the largest change shrinks to %.3g of itself in 1/64 of the step (bound 0.25; a jump: "
         "1)\n", worst);
  CHECK(worst <= 0.25);
}

static void check_far_viewers(const sf_atmosphere *atm) {
  sf_sky_raymarched m;
  sf_sky_raymarched_make(atm, SF_SKY_RAYMARCHED_STEPS, SF_RAYMARCHED_DEPTHS_FLAT, &m);
  double far[SKY_FAR_VIEWERS][4], entry[SKY_FAR_VIEWERS][4], worst = 0.0;
  int n = sky_far_viewers(atm, far, entry);
  for (int v = 0; v < n; ++v) {
    double got[SF_MAX_CHANNELS], at_entry[SF_MAX_CHANNELS];
    sf_sky_raymarched_radiance(&m, entry[v][0], entry[v][1], entry[v][2], entry[v][3], at_entry);
    sf_sky_raymarched_radiance(&m, far[v][0], far[v][1], far[v][2], far[v][3], got);
    worst = fmax(worst, sky_worst_rel(got, at_entry, atm->n_channels));
  }
  printf("viewers 1000 km to 1e6 km out vs at the entry point: worst rel %.3g (bound 1e-6)\n", worst);
  CHECK(worst <= 1e-6);
}

/* The emitted C against the double at the points and from far out. */
static void check_emitted_values(const sf_candidate *c, const sf_atmosphere *atm, sky_fn eval) {
  double worst = 0.0, worst_f32 = 0.0;
  for (int p = 0; p < SKY_POINTS; ++p) {
    double want[SF_MAX_CHANNELS], got[3];
    float emitted[3];
    c->eval(c->ctx, sky_points[p], want);
    eval((float)sky_points[p][0], (float)sky_points[p][1], (float)sky_points[p][2], (float)sky_points[p][3], emitted);
    for (int k = 0; k < 3; ++k) got[k] = emitted[k], CHECK(isfinite(got[k]) && got[k] >= 0.0);
    double e = sky_worst_rel(got, want, 3);
    float f32[3], in[4] = {(float)sky_points[p][0], (float)sky_points[p][1], (float)sky_points[p][2], (float)sky_points[p][3]};
    double f[3];
    c->eval_f32(c->ctx, 1, in, f32);
    for (int k = 0; k < 3; ++k) f[k] = f32[k];
    worst_f32 = fmax(worst_f32, sky_worst_rel(f, want, 3));
    if (e > 1e-4) printf("point %d: emitted %.6g %.6g %.6g, double %.6g %.6g %.6g\n", p, got[0], got[1], got[2],
                         want[0], want[1], want[2]);
    worst = fmax(worst, e);
  }
  /* float32 roundings of the sums, the inputs' own rounding included (a
   * float mu near the horizon moves the ray, a float nu the shadow's edges) */
  printf("emitted C vs the double: worst rel %.3g; the float32 evaluation the report times: %.3g (bounds 1e-4)\n",
         worst, worst_f32);
  CHECK(worst <= 1e-4);
  CHECK(worst_f32 <= 1e-4);
  double far[SKY_FAR_VIEWERS][4], entry[SKY_FAR_VIEWERS][4], worst_far = 0.0;
  int n_far = sky_far_viewers(atm, far, entry);
  for (int v = 0; v < n_far; ++v) {
    double at_entry[SF_MAX_CHANNELS], got[3];
    float emitted[3];
    c->eval(c->ctx, entry[v], at_entry);
    eval((float)far[v][0], (float)far[v][1], (float)far[v][2], (float)far[v][3], emitted);
    for (int k = 0; k < 3; ++k) got[k] = emitted[k];
    worst_far = fmax(worst_far, sky_worst_rel(got, at_entry, 3));
  }
  printf("emitted C, viewers 1000 km to 1e6 km out vs the double at the entry point: worst rel %.3g (bound 1e-3)\n",
         worst_far);
  CHECK(worst_far <= 1e-3);
}

/* flat: the flat sky's candidate (one step), else the raymarched sky's. */
static void check_candidate(const sf_atmosphere *atm, int flat, const char *dir, const char *base, int values) {
  sf_candidate c;
  sf_error err = {0};
  printf("-- %s, %s\n", atm->name, flat ? "flat sky" : "raymarched sky");
  if (!CHECK((flat ? sf_candidate_sky_flat : sf_candidate_sky_raymarched)(atm, &c, &err) == SF_OK)) return;
  CHECK(c.quantity == SF_CANDIDATE_SKY_RADIANCE && c.role == SF_ROLE_BASELINE && c.emit && c.eval_f32);
  CHECK(strcmp(c.name, flat ? "flat-sky" : "raymarched-sky") == 0);
  sf_sky_raymarched m;
  sf_sky_raymarched_make(atm, flat ? SF_SKY_FLAT_STEPS : SF_SKY_RAYMARCHED_STEPS, SF_RAYMARCHED_DEPTHS_FLAT, &m);
  int same = 1;
  for (int p = 0; p < SKY_POINTS; ++p) {
    double want[SF_MAX_CHANNELS], got[SF_MAX_CHANNELS];
    sf_sky_raymarched_radiance(&m, sky_points[p][0], sky_points[p][1], sky_points[p][2], sky_points[p][3], want);
    c.eval(c.ctx, sky_points[p], got);
    for (int k = 0; k < atm->n_channels; ++k) same &= got[k] == want[k];
  }
  CHECK(same);
  void *lib = NULL;
  sky_fn eval = NULL;
  CHECK(sky_emitted_load(&c, atm, dir, base, &lib, &eval) == 0);
  if (eval && values) check_emitted_values(&c, atm, eval);
  sky_check_glsl(dir, base);
  if (lib) dlclose(lib);
  sf_candidate_free(&c);
}

int main(void) {
  sf_atmosphere atm;
  sf_atmosphere_default(&atm);
  check_exp_mean();
  check_integrator(&atm);
  check_vertical_exact(&atm);
  check_seed_steps(&atm);
  check_flat_is_eq52(&atm);
  check_shadow_continuity(&atm);
  check_far_viewers(&atm);
  char dir[] = "/tmp/skyfit-sky-raymarched-XXXXXX";
  if (!mkdtemp(dir)) return 1;
  check_candidate(&atm, 0, dir, "raymarched_sky", 1);
  check_candidate(&atm, 1, dir, "flat_sky", 1);
  /* a constituent that absorbs only (but names a phase function): no
   * variable emitted that nothing reads (-Wall -Werror) */
  sf_atmosphere odd = atm;
  snprintf(odd.name, sizeof odd.name, "default with an absorber");
  sf_constituent *absorber = &odd.constituents[odd.n_constituents++];
  *absorber = atm.constituents[1];
  snprintf(absorber->name, sizeof absorber->name, "soot");
  for (int k = 0; k < odd.n_channels; ++k) absorber->scattering[k] = 0.0, absorber->absorption[k] = 2e-4 * (k + 1);
  sf_atmosphere_finalize(&odd);
  check_candidate(&odd, 0, dir, "raymarched_sky_odd", 0);
  check_candidate(&odd, 1, dir, "flat_sky_odd", 0);
  /* no exponential constituent: a scattering tent, the flat model's shell
   * alone (the ends' geometry had been emitted unread: -Werror) */
  sf_atmosphere tent = atm;
  snprintf(tent.name, sizeof tent.name, "a scattering tent alone");
  tent.n_constituents = 1;
  tent.constituents[0] = atm.constituents[2];
  snprintf(tent.constituents[0].name, sizeof tent.constituents[0].name, "haze");
  tent.constituents[0].phase.kind = SF_PHASE_ISOTROPIC;
  for (int k = 0; k < tent.n_channels; ++k) tent.constituents[0].scattering[k] = 1e-3;
  sf_atmosphere_finalize(&tent);
  check_candidate(&tent, 0, dir, "raymarched_sky_tent", 0);
  check_candidate(&tent, 1, dir, "flat_sky_tent", 0);
  /* a fifth constituent: measured, not emitted */
  sf_atmosphere five = odd;
  five.constituents[five.n_constituents++] = atm.constituents[0];
  snprintf(five.constituents[4].name, sizeof five.constituents[4].name, "more_air");
  sf_atmosphere_finalize(&five);
  sf_candidate c;
  sf_error err = {0};
  if (CHECK(sf_candidate_sky_raymarched(&five, &c, &err) == SF_OK)) {
    CHECK(c.emit == NULL && c.eval_f32 == NULL && c.eval != NULL);
    sf_candidate_free(&c);
  }
  char cmd[200];
  snprintf(cmd, sizeof cmd, "rm -rf %s", dir);
  if (system(cmd) != 0) printf("could not remove %s\n", dir);
  return check_summary();
}
