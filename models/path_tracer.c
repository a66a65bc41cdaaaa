#include "models/path_tracer.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#ifdef _OPENMP
#include <omp.h>
#endif

#include "models/density_bound.h"
#include "models/phase.h"
#include "models/phase_sampling.h"
#include "models/ray_geometry.h"
#include "models/rng.h"

#define SF_PI 3.14159265358979323846

/* Paths are rouletted from this vertex on: the first orders carry most of
 * the radiance and are never cut. */
#define ROULETTE_FROM_ORDER 4
/* A shadow ray whose ratio-tracking weight has fallen below this survives
 * with probability 1/2 (and doubles): unbiased, and it stops the long grazing
 * shadow rays of sunset from tracking through opaque air for nothing. */
#define SHADOW_ROULETTE_BELOW 0.02
/* Majorants are tabulated for rays whose lowest altitude lies in each of
 * this many shells (see segment_majorant). */
#define MAJORANT_SHELLS 128
/* Rounding slack for altitudes computed from 3D points, km. */
#define ALTITUDE_SLACK_KM 1e-6
/* Samples are summed in at most this many blocks, merged in order. */
#define MAX_BLOCKS 4096
#define MIN_BLOCK_SAMPLES 64

typedef struct vec3 {
  double x, y, z;
} vec3;

static vec3 v3(double x, double y, double z) { vec3 v = {x, y, z}; return v; }
static vec3 v3_add_scaled(vec3 a, vec3 d, double t) { return v3(a.x + t * d.x, a.y + t * d.y, a.z + t * d.z); }
static vec3 v3_scale(vec3 a, double s) { return v3(a.x * s, a.y * s, a.z * s); }
static double v3_dot(vec3 a, vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static double v3_length(vec3 a) { return sqrt(v3_dot(a, a)); }
static vec3 v3_normalized(vec3 a) { return v3_scale(a, 1.0 / v3_length(a)); }

/* Orthonormal basis (b1, b2) completing the unit vector n (Duff et al. 2017). */
static void orthonormal_basis(vec3 n, vec3 *b1, vec3 *b2) {
  double sign = n.z >= 0.0 ? 1.0 : -1.0;
  double a = -1.0 / (sign + n.z);
  double b = n.x * n.y * a;
  *b1 = v3(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x);
  *b2 = v3(b, sign + n.y * n.y * a, -n.y);
}

/* Direction at cosine cos_theta from axis, azimuth phi. */
static vec3 direction_around(vec3 axis, double cos_theta, double phi) {
  vec3 b1, b2;
  orthonormal_basis(axis, &b1, &b2);
  double sin_theta = sqrt(fmax(0.0, (1.0 - cos_theta) * (1.0 + cos_theta)));
  double c = sin_theta * cos(phi), s = sin_theta * sin(phi);
  vec3 d = v3(cos_theta * axis.x + c * b1.x + s * b2.x, cos_theta * axis.y + c * b1.y + s * b2.y,
              cos_theta * axis.z + c * b1.z + s * b2.z);
  return v3_normalized(d);
}

/* What the paths of one channel see: the constituents with extinction in it. */
typedef struct channel_medium {
  double bottom_radius, top_radius;
  int n;
  const sf_constituent *constituent[SF_MAX_CONSTITUENTS];
  double extinction[SF_MAX_CONSTITUENTS];
  double scattering[SF_MAX_CONSTITUENTS];
  /* majorant_above[k] >= the extinction at every altitude from
   * k * shell_height to the top: a ray that never dips below that altitude
   * can be tracked against it. [0] bounds the whole atmosphere. */
  double shell_height;
  double majorant_above[MAJORANT_SHELLS];
  double sun_irradiance, ground_albedo;
  vec3 sun;
} channel_medium;

static void channel_medium_make(const sf_atmosphere *atm, int ch, vec3 sun, channel_medium *m) {
  memset(m, 0, sizeof *m);
  m->bottom_radius = atm->bottom_radius_km;
  m->top_radius = atm->top_radius_km;
  m->sun_irradiance = atm->sun_irradiance[ch];
  m->ground_albedo = atm->ground_albedo[ch];
  m->sun = sun;
  for (int i = 0; i < atm->n_constituents; ++i) {
    double ext = sf_extinction(atm, i, ch);
    if (!(ext > 0.0)) continue;
    m->constituent[m->n] = &atm->constituents[i];
    m->extinction[m->n] = ext;
    m->scattering[m->n] = atm->constituents[i].scattering[ch];
    ++m->n;
  }
  double thickness = m->top_radius - m->bottom_radius;
  double h_top = thickness + ALTITUDE_SLACK_KM * (1.0 + thickness);
  m->shell_height = thickness / MAJORANT_SHELLS;
  for (int k = 0; k < MAJORANT_SHELLS; ++k) {
    double h_lo = k == 0 ? -ALTITUDE_SLACK_KM : k * m->shell_height;
    double bound = 0.0;
    for (int i = 0; i < m->n; ++i)
      bound += m->extinction[i] * sf_constituent_max_density(m->constituent[i], h_lo, h_top);
    m->majorant_above[k] = bound * (1.0 + 1e-12);   /* rounding of the profile formulas */
  }
}

/* Majorant for the segment [0, t_max] of the ray (x, d): the table entry for
 * the segment's lowest altitude (its closest approach to the planet centre,
 * or an end). High and grazing rays are tracked against the thin air they
 * actually cross instead of the density at the ground. */
static double segment_majorant(const channel_medium *m, vec3 x, vec3 d, double t_max) {
  double r = v3_length(x);
  double mu = v3_dot(x, d) / r;
  double r_min = r;
  if (mu < 0.0) {
    r_min = -r * mu < t_max ? sqrt(sf_ray_closest_radius_sq(r, mu)) : sf_ray_radius_at(r, mu, t_max);
    if (r_min > r) r_min = r;
  }
  double h_min = r_min - m->bottom_radius - ALTITUDE_SLACK_KM;
  int k = h_min > 0.0 ? (int)(h_min / m->shell_height) : 0;
  if (k >= MAJORANT_SHELLS) k = MAJORANT_SHELLS - 1;
  return m->majorant_above[k];
}

/* Densities at point p and the extinction they make. */
static double extinction_at(const channel_medium *m, vec3 p, double *rho) {
  double h = v3_length(p) - m->bottom_radius;
  double sigma_t = 0.0;
  for (int i = 0; i < m->n; ++i) {
    rho[i] = sf_constituent_density(m->constituent[i], h);
    sigma_t += m->extinction[i] * rho[i];
  }
  return sigma_t;
}

static double free_flight(double majorant, sf_rng *rng) {
  return -log1p(-sf_rng_uniform(rng)) / majorant;   /* seed 000 eq. 11 */
}

/* Transmittance from x to the sun, 0 in the planet's shadow: ratio tracking,
 * seed 000 eq. 13 (an unbiased estimate of exp(-optical depth)). */
static double sun_transmittance(const channel_medium *m, vec3 x, sf_rng *rng) {
  double r = v3_length(x);
  double mu = v3_dot(x, m->sun) / r;
  if (sf_ray_hits_sphere_from_above(r, mu, m->bottom_radius)) return 0.0;
  double t_near, t_far;
  if (!sf_ray_sphere_intersections(r, mu, m->top_radius, &t_near, &t_far)) return 1.0;
  double majorant = segment_majorant(m, x, m->sun, t_far);
  if (!(majorant > 0.0)) return 1.0;
  double rho[SF_MAX_CONSTITUENTS];
  double transmittance = 1.0, t = 0.0;
  for (;;) {
    t += free_flight(majorant, rng);
    if (!(t < t_far)) return transmittance;
    transmittance *= 1.0 - extinction_at(m, v3_add_scaled(x, m->sun, t), rho) / majorant;
    if (transmittance < SHADOW_ROULETTE_BELOW) {
      if (!(transmittance > 0.0) || sf_rng_uniform(rng) < 0.5) return 0.0;
      transmittance *= 2.0;
    }
  }
}

/* Delta tracking (seed 000 eq. 11-12) from x along d up to t_max. Returns 1
 * at a real collision, with its point, densities and extinction. */
static int delta_track(const channel_medium *m, vec3 x, vec3 d, double t_max, sf_rng *rng,
                       vec3 *p, double *rho, double *sigma_t) {
  double majorant = segment_majorant(m, x, d, t_max);
  if (!(majorant > 0.0)) return 0;
  double t = 0.0;
  for (;;) {
    t += free_flight(majorant, rng);
    if (!(t < t_max)) return 0;
    *p = v3_add_scaled(x, d, t);
    *sigma_t = extinction_at(m, *p, rho);
    if (sf_rng_uniform(rng) * majorant < *sigma_t) return 1;
  }
}

/* The segment of the ray (x, d) inside the atmosphere, from x. x is inside
 * (up to rounding), so where it starts is x itself. */
static int next_segment(const channel_medium *m, vec3 x, vec3 d, double *t_max, int *hits_ground) {
  double r = v3_length(x);
  double mu = v3_dot(x, d) / r;
  double t_enter, t_exit;
  if (!sf_ray_atmosphere_segment(r, mu, m->bottom_radius, m->top_radius, &t_enter, &t_exit,
                                 hits_ground))
    return 0;
  *t_max = t_exit;
  return t_exit > 0.0;
}

/* One backward path from x along d; (t_max, hits_ground) is its first
 * segment. Returns the radiance it estimates. */
static double trace_path(const channel_medium *m, vec3 x, vec3 d, double t_max, int hits_ground,
                         int max_order, sf_rng *rng) {
  double radiance = 0.0, weight = 1.0;
  double rho[SF_MAX_CONSTITUENTS];
  int order = 0;
  for (;;) {
    vec3 p;
    double sigma_t;
    if (delta_track(m, x, d, t_max, rng, &p, rho, &sigma_t)) {
      ++order;
      double sigma_s = 0.0, phase_sun = 0.0;
      double nu_sun = v3_dot(d, m->sun);
      for (int i = 0; i < m->n; ++i) {
        double s = m->scattering[i] * rho[i];
        sigma_s += s;
        if (s > 0.0) phase_sun += s * sf_phase_value(&m->constituent[i]->phase, nu_sun);
      }
      if (!(sigma_s > 0.0)) break;                 /* absorbed */
      weight *= sigma_s / sigma_t;                 /* single-scattering albedo */
      if (phase_sun > 0.0)
        radiance += weight * m->sun_irradiance * (phase_sun / sigma_s) * sun_transmittance(m, p, rng);
      if (max_order > 0 && order >= max_order) break;
      /* Pick the constituent that scatters, in proportion to its share. */
      double pick = sf_rng_uniform(rng) * sigma_s;
      int k = -1;
      for (int i = 0; i < m->n; ++i) {
        double s = m->scattering[i] * rho[i];
        if (!(s > 0.0)) continue;
        k = i;                  /* the last one that scatters absorbs rounding */
        if (pick < s) break;
        pick -= s;
      }
      const sf_phase *phase = &m->constituent[k]->phase;
      double nu = sf_phase_sample_nu(phase, rng);
      weight *= sf_phase_value(phase, nu) / sf_phase_sample_pdf(phase, nu);
      if (!(weight > 0.0)) break;
      d = direction_around(d, nu, 2.0 * SF_PI * sf_rng_uniform(rng));
      x = p;
    } else {
      /* Past t_max: to space, or onto the ground. The ground at the end of
       * the view ray itself is not part of the sky radiance. */
      if (!hits_ground || order == 0) break;
      ++order;
      vec3 n = v3_normalized(v3_add_scaled(x, d, t_max));
      x = v3_scale(n, m->bottom_radius);
      double albedo = m->ground_albedo;
      if (!(albedo > 0.0)) break;
      double cos_sun = v3_dot(n, m->sun);
      /* Lambertian BRDF albedo/pi; no planet shadow on a lit face. */
      if (cos_sun > 0.0)
        radiance += weight * albedo / SF_PI * m->sun_irradiance * cos_sun * sun_transmittance(m, x, rng);
      if (max_order > 0 && order >= max_order) break;
      weight *= albedo;      /* BRDF cos / (cos/pi) for a cosine-sampled bounce */
      double u = sf_rng_uniform(rng);
      d = direction_around(n, sqrt(1.0 - u), 2.0 * SF_PI * sf_rng_uniform(rng));
    }
    if (order >= ROULETTE_FROM_ORDER) {
      double survive = weight < 1.0 ? weight : 1.0;
      if (!(sf_rng_uniform(rng) < survive)) break;
      weight /= survive;
    }
    if (!next_segment(m, x, d, &t_max, &hits_ground)) break;
  }
  return radiance;
}

/* nu clamped into [mu mu_s - sqrt((1-mu^2)(1-mu_s^2)), mu mu_s + sqrt(...)]
 * (SPEC §3). */
static double clamp_nu(double mu, double mu_s, double nu) {
  double spread = sqrt(fmax(0.0, (1.0 - mu) * (1.0 + mu) * (1.0 - mu_s) * (1.0 + mu_s)));
  double lo = mu * mu_s - spread, hi = mu * mu_s + spread;
  if (lo < -1.0) lo = -1.0;
  if (hi > 1.0) hi = 1.0;
  return nu < lo ? lo : (nu > hi ? hi : nu);
}

/* Sun direction s with s.z = mu_s and s.v = nu for v = (sin_v, 0, mu). */
static vec3 sun_direction(double mu, double mu_s, double nu) {
  double sin_v = sqrt(fmax(0.0, (1.0 - mu) * (1.0 + mu)));
  double sin_s = sqrt(fmax(0.0, (1.0 - mu_s) * (1.0 + mu_s)));
  double sx = sin_v > 0.0 ? (nu - mu * mu_s) / sin_v : sin_s;
  if (sx > sin_s) sx = sin_s;
  if (sx < -sin_s) sx = -sin_s;
  double sy = sqrt(fmax(0.0, (sin_s - sx) * (sin_s + sx)));
  return v3(sx, sy, mu_s);
}

/* Running mean and sum of squared deviations (Welford; Chan et al. merge). */
typedef struct running_stats {
  double n, mean, m2;
} running_stats;

static void stats_add(running_stats *s, double x) {
  s->n += 1.0;
  double delta = x - s->mean;
  s->mean += delta / s->n;
  s->m2 += delta * (x - s->mean);
}

static void stats_merge(running_stats *into, const running_stats *b) {
  if (b->n == 0.0) return;
  if (into->n == 0.0) { *into = *b; return; }
  double n = into->n + b->n;
  double delta = b->mean - into->mean;
  into->mean += delta * (b->n / n);
  into->m2 += b->m2 + delta * delta * (into->n * b->n / n);
  into->n = n;
}

static int check_inputs(const sf_atmosphere *atm, double h_km, double mu, double mu_s, double nu,
                        const sf_path_tracer_options *opt, sf_error *err) {
  if (!atm || !opt) return sf_fail(err, SF_ERR_INPUT, "path tracer: no atmosphere or options");
  if (atm->n_channels < 1 || atm->n_channels > SF_MAX_CHANNELS)
    return sf_fail(err, SF_ERR_INPUT, "path tracer: %d channels (1..%d allowed)", atm->n_channels,
                   SF_MAX_CHANNELS);
  if (!(atm->bottom_radius_km > 0.0 && atm->top_radius_km > atm->bottom_radius_km &&
        isfinite(atm->top_radius_km)))
    return sf_fail(err, SF_ERR_INPUT, "path tracer: radii must satisfy 0 < bottom < top, got %g, %g",
                   atm->bottom_radius_km, atm->top_radius_km);
  if (!(isfinite(h_km) && h_km >= 0.0))
    return sf_fail(err, SF_ERR_INPUT, "path tracer: viewer altitude must be finite and >= 0, got %g", h_km);
  if (!(mu >= -1.0 && mu <= 1.0))
    return sf_fail(err, SF_ERR_INPUT, "path tracer: mu must be in [-1, 1], got %g", mu);
  if (!(mu_s >= -1.0 && mu_s <= 1.0))
    return sf_fail(err, SF_ERR_INPUT, "path tracer: mu_s must be in [-1, 1], got %g", mu_s);
  if (!isfinite(nu)) return sf_fail(err, SF_ERR_INPUT, "path tracer: nu must be finite, got %g", nu);
  if (opt->samples < 1)
    return sf_fail(err, SF_ERR_INPUT, "path tracer: samples must be >= 1, got %lld", opt->samples);
  if (opt->max_order < 0)
    return sf_fail(err, SF_ERR_INPUT, "path tracer: max_order must be >= 0, got %d", opt->max_order);
  if (opt->threads < 0)
    return sf_fail(err, SF_ERR_INPUT, "path tracer: threads must be >= 0, got %d", opt->threads);
  for (int ch = 0; ch < atm->n_channels; ++ch)
    if (!(isfinite(atm->sun_irradiance[ch]) && isfinite(atm->ground_albedo[ch]) &&
          atm->ground_albedo[ch] >= 0.0))
      return sf_fail(err, SF_ERR_INPUT,
                     "path tracer: channel %d: sun irradiance and ground albedo must be finite, "
                     "albedo >= 0", ch);
  return SF_OK;
}

int sf_path_trace_sky_radiance(const sf_atmosphere *atm, double h_km, double mu, double mu_s,
                               double nu, const sf_path_tracer_options *opt,
                               sf_path_tracer_result *out, sf_error *err) {
  int status = check_inputs(atm, h_km, mu, mu_s, nu, opt, err);
  if (status != SF_OK) return status;
  memset(out, 0, sizeof *out);
  out->samples = opt->samples;
  int n_channels = atm->n_channels;

  double r_view = atm->bottom_radius_km + h_km;
  double t_enter, t_exit;
  int hits_ground;
  if (!sf_ray_atmosphere_segment(r_view, mu, atm->bottom_radius_km, atm->top_radius_km, &t_enter,
                                 &t_exit, &hits_ground) ||
      !(t_exit > t_enter))
    return SF_OK;                              /* never inside the atmosphere: no sky */
  vec3 view = v3(sqrt(fmax(0.0, (1.0 - mu) * (1.0 + mu))), 0.0, mu);
  vec3 start = v3_add_scaled(v3(0.0, 0.0, r_view), view, t_enter);
  double t_first = t_exit - t_enter;
  vec3 sun = sun_direction(mu, mu_s, clamp_nu(mu, mu_s, nu));

  channel_medium *media = malloc(sizeof *media * (size_t)n_channels);
  long long block_samples = (opt->samples + MAX_BLOCKS - 1) / MAX_BLOCKS;
  if (block_samples < MIN_BLOCK_SAMPLES) block_samples = MIN_BLOCK_SAMPLES;
  long long n_blocks = (opt->samples + block_samples - 1) / block_samples;
  running_stats *blocks = calloc((size_t)(n_blocks * n_channels), sizeof *blocks);
  if (!media || !blocks) {
    free(media);
    free(blocks);
    return sf_fail(err, SF_ERR_INTERNAL, "path tracer: out of memory");
  }
  for (int ch = 0; ch < n_channels; ++ch) channel_medium_make(atm, ch, sun, &media[ch]);

  int threads = opt->threads;
#ifdef _OPENMP
  if (threads == 0) threads = omp_get_max_threads();
#endif
  /* No more threads than blocks: a small call stays serial, which matters
   * when a caller makes many of them. */
  if (threads > n_blocks) threads = (int)n_blocks;
  if (threads < 1) threads = 1;
#ifdef _OPENMP
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads) if (threads > 1)
#endif
  for (long long b = 0; b < n_blocks; ++b) {
    long long first = b * block_samples;
    long long last = first + block_samples < opt->samples ? first + block_samples : opt->samples;
    running_stats *stats = &blocks[b * n_channels];
    for (long long i = first; i < last; ++i) {
      for (int ch = 0; ch < n_channels; ++ch) {
        double value = 0.0;
        if (media[ch].majorant_above[0] > 0.0) {
          sf_rng rng;
          sf_rng_seed(&rng, opt->seed, (uint64_t)i, (uint64_t)ch);
          value = trace_path(&media[ch], start, view, t_first, hits_ground, opt->max_order, &rng);
        }
        stats_add(&stats[ch], value);
      }
    }
  }
  (void)threads;

  for (int ch = 0; ch < n_channels; ++ch) {
    running_stats total = {0.0, 0.0, 0.0};
    for (long long b = 0; b < n_blocks; ++b) stats_merge(&total, &blocks[b * n_channels + ch]);
    out->radiance[ch] = total.mean;
    out->std_error[ch] = total.n > 1.0 ? sqrt(total.m2 / (total.n - 1.0) / total.n) : 0.0;
  }
  free(media);
  free(blocks);
  return SF_OK;
}
