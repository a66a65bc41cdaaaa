#include "fit/segment_samples.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "models/ray_geometry.h"
#include "models/rng.h"
#include "util/constants.h"

int sf_segment_samples_make(const sf_scene_domain *d, double bottom_radius_km, double top_radius_km,
                            sf_candidate_quantity q, size_t n, uint64_t seed, sf_domain_samples *out,
                            sf_error *err) {
  memset(out, 0, sizeof *out);
  if (n == 0) return sf_fail(err, SF_ERR_INPUT, "no segments asked for");
  int ray_inputs = sf_candidate_n_inputs(q);
  out->quantity = q;
  out->n_inputs = ray_inputs + 1;
  out->inputs = malloc(sizeof(double) * n * (size_t)out->n_inputs);
  if (!out->inputs) return sf_fail(err, SF_ERR_INTERNAL, "out of memory for %zu segments", n);
  sf_rng rng;
  sf_rng_seed(&rng, seed, 0x7365676d656e74ULL /* "segment" */, (uint64_t)q);
  size_t got = 0;
  for (size_t draw = 0; got < n && draw < SF_SEGMENT_SAMPLES_MAX_DRAWS * n; ++draw) {
    /* a ray drawn as sf_domain_samples_make draws its rays (from a stream
     * of its own: not the same rays), then where its segment ends */
    double h = d->h_min_km + (d->h_max_km - d->h_min_km) * sf_rng_uniform(&rng);
    double mu = d->mu_min + (d->mu_max - d->mu_min) * sf_rng_uniform(&rng);
    double mu_s = d->mu_s_min + (d->mu_s_max - d->mu_s_min) * sf_rng_uniform(&rng);
    double phi = SF_PI * sf_rng_uniform(&rng);
    double u = sf_rng_uniform(&rng);
    double t_enter, t_exit;
    int ground;
    if (!sf_ray_atmosphere_segment(bottom_radius_km + h, mu, bottom_radius_km, top_radius_km, &t_enter, &t_exit,
                                   &ground) ||
        !(t_exit > t_enter))
      continue;   /* never in the air: no segment to measure */
    double *p = out->inputs + got * (size_t)out->n_inputs;
    p[0] = h;
    p[1] = mu;
    if (ray_inputs == 4) {
      double nu = mu * mu_s + sqrt(fmax(0.0, (1.0 - mu * mu) * (1.0 - mu_s * mu_s))) * cos(phi);
      p[2] = mu_s;
      p[3] = fmax(-1.0, fmin(1.0, nu));
    }
    p[ray_inputs] = t_enter + u * (t_exit - t_enter);
    ++got;
  }
  out->n = got;
  return SF_OK;
}
