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
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "sky_baseline_checks.h"
#include "fit/candidate_builtin.h"
#include "models/atmosphere_file.h"
#include "models/sky_naive.h"

static void check_convergence(const sf_atmosphere *atm) {
  sf_sky_naive fine = {atm, 4096, 1024}, coarse = {atm, SF_SKY_NAIVE_VIEW_STEPS, SF_SKY_NAIVE_SUN_STEPS};
  double worst_fine = 0.0, worst_coarse = 0.0;
  for (int p = 0; p < SKY_POINTS; ++p) {
    double want[4], got[4], got_coarse[4];
    sky_reference(atm, sky_points[p], SF_SINGLE_SCATTERING_REL_TOL, want);
    sf_sky_naive_radiance(&fine, sky_points[p][0], sky_points[p][1], sky_points[p][2], sky_points[p][3], got);
    sf_sky_naive_radiance(&coarse, sky_points[p][0], sky_points[p][1], sky_points[p][2], sky_points[p][3], got_coarse);
    double e = sky_worst_rel(got, want, atm->n_channels), ec = sky_worst_rel(got_coarse, want, atm->n_channels);
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

static void check_emitted(const sf_atmosphere *atm, const char *dir, const char *base) {
  sf_candidate c;
  sf_error err = {0};
  if (!CHECK(sf_candidate_sky_naive(atm, &c, &err) == SF_OK)) return;
  CHECK(c.quantity == SF_CANDIDATE_SKY_RADIANCE && c.role == SF_ROLE_BASELINE && c.emit && c.eval_f32);
  printf("-- %s\n", atm->name);
  void *lib = NULL;
  sky_fn eval = NULL;
  CHECK(sky_emitted_load(&c, atm, dir, base, &lib, &eval) == 0);
  double worst_emitted = 0.0, worst_f32 = 0.0;
  for (int p = 0; eval && p < SKY_POINTS; ++p) {
    double want[4];
    float emitted[3], f32[3], in[4] = {(float)sky_points[p][0], (float)sky_points[p][1], (float)sky_points[p][2],
                                       (float)sky_points[p][3]};
    c.eval(c.ctx, sky_points[p], want);
    eval(in[0], in[1], in[2], in[3], emitted);
    c.eval_f32(c.ctx, 1, in, f32);
    double e[3], f[3];
    for (int k = 0; k < 3; ++k) e[k] = emitted[k], f[k] = f32[k];
    worst_emitted = fmax(worst_emitted, sky_worst_rel(e, want, 3));
    worst_f32 = fmax(worst_f32, sky_worst_rel(f, want, 3));
  }
  /* float32 roundings of the sums (the inputs' own rounding included: a
   * float mu near the horizon moves the ray) */
  printf("emitted C vs the double: worst rel %.3g; float32 evaluation vs the double: %.3g (bounds 1e-4)\n",
         worst_emitted, worst_f32);
  CHECK(worst_emitted <= 1e-4);
  CHECK(worst_f32 <= 1e-4);
  /* far viewers: the values at the ray's entry */
  double far[SKY_FAR_VIEWERS][4], entry[SKY_FAR_VIEWERS][4];
  int n_far = sky_far_viewers(atm, far, entry);
  double worst_far = 0.0, worst_far_emitted = 0.0;
  for (int v = 0; eval && v < n_far; ++v) {
    double got[4], at_entry[4];
    c.eval(c.ctx, entry[v], at_entry);
    c.eval(c.ctx, far[v], got);
    float emitted[3];
    eval((float)far[v][0], (float)far[v][1], (float)far[v][2], (float)far[v][3], emitted);
    double e[3] = {emitted[0], emitted[1], emitted[2]};
    worst_far = fmax(worst_far, sky_worst_rel(got, at_entry, 3));
    worst_far_emitted = fmax(worst_far_emitted, sky_worst_rel(e, at_entry, 3));
  }
  printf("viewers 1000 km to 1e6 km out vs at the entry point: double %.3g (bound 1e-6), emitted C %.3g (bound "
         "1e-3)\n", worst_far, worst_far_emitted);
  CHECK(worst_far <= 1e-6);
  CHECK(worst_far_emitted <= 1e-3);
  sky_check_glsl(dir, base);
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
