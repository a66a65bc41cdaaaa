/* Random inputs drawn around the SPEC §10 hard cases, per case class, for
 * the float32 sweep of emitted headers (tests/test_float32_sweep.c).
 * A point is up to 8 floats in the emitted function's argument order; its
 * layout is given by the function's input kind. Everything is drawn from a
 * seeded 64-bit LCG, so a sweep is reproducible. */
#ifndef SKYFIT_TESTS_HARD_CASE_POINTS_H
#define SKYFIT_TESTS_HARD_CASE_POINTS_H

#include <float.h>
#include <math.h>
#include <stdint.h>

#include "models/atmosphere.h"
#include "models/ray_geometry.h"

typedef enum hard_case_class {
  HC_DOMAIN = 0,    /* anywhere: viewers from the ground to 5 planet radii out, any direction */
  HC_TANGENT,       /* mu at the ground's horizon cosine: exact, +-1e-6 relative, +-1..64 ulp */
  HC_GROUND_DOWN,   /* h = 0 (or within 1 m) looking down, mu in [-1, 0] */
  HC_TOP_UP,        /* at the top boundary (exactly, or 1e-7 relative off) looking up */
  HC_SPACE,         /* above the top: rays that miss, graze (+-1e-6) or enter the atmosphere */
  HC_SUN_SHADOW,    /* sun below the horizon, in the planet's shadow, at the terminator */
  HC_UNIT,          /* mu, mu_s, nu = +-1 (and 1 ulp inside) */
  HC_SEGMENT,       /* segments: t = 0, tiny, at the ray's end +-1e-6 relative, beyond it */
  HC_DEEP,          /* T -> 0: long rays grazing the ground at low altitude */
  HC_COUNT
} hard_case_class;

static const char *const hard_case_names[HC_COUNT] = {"domain", "tangent", "h0-down", "top-up", "space",
                                                      "sun-shadow", "+-1", "segment", "T->0"};

/* The arguments of an emitted function. */
typedef enum hard_case_input {
  HI_RAY = 0,   /* (h, mu) */
  HI_RAY_T,     /* (h, mu, t) */
  HI_RAY_T0T1,  /* (h, mu, t0, t1) */
  HI_SKY,       /* (h, mu, mu_s, nu) */
  HI_SKY_T,     /* (h, mu, mu_s, nu, t) */
  HI_GROUND,    /* (mu, mu_s, nu): a viewer on the ground */
  HI_VEC4,      /* a radiance vec4 */
  HI_INDEX,     /* an int (constituent index), given as a float */
  HI_NONE
} hard_case_input;

typedef struct hard_case_rng {
  uint64_t state;
} hard_case_rng;

static inline double hc_uniform(hard_case_rng *g) {
  g->state = g->state * 6364136223846793005ull + 1442695040888963407ull;
  return (double)(g->state >> 11) * (1.0 / 9007199254740992.0);
}
static inline double hc_range(hard_case_rng *g, double lo, double hi) { return lo + (hi - lo) * hc_uniform(g); }
static inline double hc_log_range(hard_case_rng *g, double lo, double hi) {
  return exp(log(lo) + (log(hi) - log(lo)) * hc_uniform(g));
}
static inline float hc_sign(hard_case_rng *g) { return hc_uniform(g) < 0.5 ? -1.0f : 1.0f; }

/* Does a class make sense for these inputs? */
static inline int hard_case_applies(hard_case_input in, hard_case_class c) {
  int ray = in == HI_RAY || in == HI_RAY_T || in == HI_RAY_T0T1;
  int sky = in == HI_SKY || in == HI_SKY_T;
  switch (c) {
    case HC_DOMAIN: return 1;
    case HC_TANGENT: case HC_GROUND_DOWN: case HC_UNIT: return ray || sky || in == HI_GROUND;
    case HC_TOP_UP: case HC_SPACE: return ray || sky;
    case HC_SUN_SHADOW: return sky || in == HI_GROUND;
    case HC_SEGMENT: return in == HI_RAY_T || in == HI_RAY_T0T1 || in == HI_SKY_T;
    case HC_DEEP: return ray || sky || in == HI_VEC4;
    default: return 0;
  }
}

/* mu near a reference cosine c: exactly float(c), c (1 +- 1e-6 u), or
 * 1..64 float ulps either side; clamped into [-1, 1]. */
static inline float hc_near_cosine(hard_case_rng *g, double c) {
  double pick = hc_uniform(g);
  float m = (float)c;   /* 30%: exactly */
  if (pick >= 0.3 && pick < 0.65) {
    m = (float)(c * (1.0 + hc_sign(g) * 1e-6 * hc_uniform(g)));
  } else if (pick >= 0.65) {
    int k = 1 + (int)(64.0 * hc_uniform(g));
    float dir = hc_sign(g) * 2.0f;
    for (int i = 0; i < k; ++i) m = nextafterf(m, dir);
  }
  return fminf(fmaxf(m, -1.0f), 1.0f);
}

/* A cosine: +-1, 1 ulp inside +-1, or uniform. */
static inline float hc_unit_or_any(hard_case_rng *g, double p_unit) {
  if (hc_uniform(g) >= p_unit) return (float)hc_range(g, -1.0, 1.0);
  float s = hc_sign(g);
  return hc_uniform(g) < 0.7 ? s : nextafterf(s, 0.0f);
}

/* A viewer altitude: 85% inside (denser low), 15% in space up to 5 planet radii out. */
static inline double hc_altitude(hard_case_rng *g, double z, double R) {
  if (hc_uniform(g) < 0.85) return z * pow(hc_uniform(g), 2.0);
  return z + hc_log_range(g, 1e-3, 5.0 * R);
}

/* Distance along a ray: 30 z u^2 (mostly inside the atmosphere, some past the end). */
static inline double hc_distance(hard_case_rng *g, double z) { return 30.0 * z * pow(hc_uniform(g), 2.0); }

/* The ray's end as double geometry sees it (0 if it never enters). */
static inline void hc_ray_extent(const sf_atmosphere *atm, double h, double mu, double *t_enter, double *t_exit) {
  double R = atm->bottom_radius_km, Rt = atm->top_radius_km;
  int ground;
  if (!sf_ray_atmosphere_segment(R + fmax(h, 0.0), mu, R, Rt, t_enter, t_exit, &ground)) *t_enter = *t_exit = 0.0;
}

/* A distance that stresses a segment of the ray (h, mu): 0, tiny, at the
 * end +- 1e-6 relative or +- a little, just past the entry (space), beyond
 * the end, huge, or a renderer's "no hit" (FLT_MAX, infinity). */
static inline double hc_segment_distance(hard_case_rng *g, const sf_atmosphere *atm, double h, double mu) {
  double t_enter, t_exit;
  hc_ray_extent(atm, h, mu, &t_enter, &t_exit);
  double pick = hc_uniform(g);
  if (pick < 0.1) return 0.0;
  if (pick < 0.35) return t_enter + hc_log_range(g, 1e-7, 1e-2);
  if (pick < 0.6) return t_exit * (1.0 + hc_sign(g) * 1e-6 * hc_uniform(g));
  if (pick < 0.75) return fmax(t_exit + hc_sign(g) * hc_log_range(g, 1e-4, 1e-1), 0.0);
  if (pick < 0.85) return t_exit * hc_range(g, 1.0, 1e3) + 1e-3;
  if (pick < 0.9) return t_enter > 0.0 ? t_enter * (1.0 + hc_sign(g) * 1e-6 * hc_uniform(g)) : 1e7;
  if (pick < 0.92) return 1e7;
  if (pick < 0.935) return FLT_MAX;
  if (pick < 0.95) return INFINITY;
  return hc_range(g, 0.0, t_exit);
}

/* (h, mu) of a ray class. */
static inline void hc_ray(hard_case_rng *g, hard_case_class c, const sf_atmosphere *atm, float *h_out,
                          float *mu_out) {
  double R = atm->bottom_radius_km, Rt = atm->top_radius_km, z = Rt - R;
  double h = hc_altitude(g, z, R), mu = hc_range(g, -1.0, 1.0);
  float hf, muf;
  switch (c) {
    case HC_TANGENT: {
      h = hc_uniform(g) < 0.8 ? (hc_uniform(g) < 0.1 ? z : hc_log_range(g, 1e-4, z)) : z + hc_log_range(g, 1e-3, 5.0 * R);
      hf = (float)h;
      muf = hc_near_cosine(g, sf_horizon_mu(R + (double)hf, R));
      break;
    }
    case HC_GROUND_DOWN: {
      double pick = hc_uniform(g);
      hf = pick < 0.5 ? 0.0f : pick < 0.55 ? -0.0f : (float)hc_log_range(g, 1e-7, 1e-3);
      pick = hc_uniform(g);
      muf = pick < 0.15 ? -1.0f : pick < 0.2 ? nextafterf(-1.0f, 0.0f) : pick < 0.25 ? -0.0f : pick < 0.3 ? 0.0f
            : pick < 0.4 ? -(float)hc_log_range(g, 1e-8, 1e-3) : -(float)hc_uniform(g);
      break;
    }
    case HC_TOP_UP: {
      double pick = hc_uniform(g);
      hf = pick < 0.5 ? (float)z : (float)(z * (1.0 + hc_sign(g) * 1e-7 * hc_uniform(g)));
      if (pick >= 0.5 && pick < 0.6) hf = nextafterf((float)z, hc_sign(g) * 1e30f);
      pick = hc_uniform(g);
      muf = pick < 0.2 ? 1.0f : pick < 0.25 ? nextafterf(1.0f, 0.0f) : pick < 0.35 ? 0.0f
            : pick < 0.45 ? (float)hc_log_range(g, 1e-8, 1e-3) : (float)hc_uniform(g);
      break;
    }
    case HC_SPACE: {
      h = z + hc_log_range(g, 1e-3, 5.0 * R);
      hf = (float)h;
      double r = R + (double)hf, top = sf_horizon_mu(r, Rt), ground = sf_horizon_mu(r, R);
      double pick = hc_uniform(g);
      if (pick < 0.35) muf = hc_near_cosine(g, top);                                   /* grazes the top */
      else if (pick < 0.55) muf = (float)hc_range(g, top, 1.0);                        /* misses */
      else if (pick < 0.8) muf = (float)hc_range(g, ground, top);                      /* through the air */
      else if (pick < 0.9) muf = hc_near_cosine(g, ground);                            /* grazes the ground */
      else muf = (float)hc_range(g, -1.0, ground);                                     /* hits the ground */
      break;
    }
    case HC_UNIT:
      hf = (float)h;
      muf = hc_unit_or_any(g, 1.0);
      break;
    case HC_DEEP: {
      hf = (float)(0.05 * z * pow(hc_uniform(g), 2.0));
      double hz = hf > 0.0f ? sf_horizon_mu(R + (double)hf, R) : 0.0;
      double pick = hc_uniform(g);
      if (pick < 0.5) muf = (float)(hz - hc_log_range(g, 1e-7, 0.05));       /* long rays to the ground */
      else if (pick < 0.9) muf = (float)(hz + hc_log_range(g, 1e-7, 0.02));  /* long rays past the tangent point */
      else muf = hf > 0.0f ? (float)hz : -0.0f;
      muf = fminf(fmaxf(muf, -1.0f), 1.0f);
      break;
    }
    case HC_SEGMENT: {
      double pick = hc_uniform(g);
      hf = (float)h;
      muf = pick < 0.2 ? hc_near_cosine(g, sf_horizon_mu(R + fmax((double)hf, 1e-4), R)) : (float)mu;
      break;
    }
    default:
      hf = (float)h;
      muf = (float)mu;
  }
  *h_out = hf;
  *mu_out = muf;
}

/* The sun (mu_s, nu) of a class for a viewer at altitude h looking along mu. */
static inline void hc_sun(hard_case_rng *g, hard_case_class c, const sf_atmosphere *atm, float h, float *mu_s,
                          float *nu) {
  double R = atm->bottom_radius_km;
  *mu_s = (float)hc_range(g, -1.0, 1.0);
  *nu = (float)hc_range(g, -1.0, 1.0);
  if (c == HC_SUN_SHADOW) {
    double hz = h > 0.0f ? sf_horizon_mu(R + (double)h, R) : 0.0;   /* below it: the viewer is in shadow */
    double pick = hc_uniform(g);
    if (pick < 0.5) *mu_s = (float)hc_range(g, -1.0, hz);
    else if (pick < 0.7) *mu_s = (float)hc_range(g, hz, 0.0);
    else if (pick < 0.9) *mu_s = hc_near_cosine(g, hz);                    /* the terminator */
    else *mu_s = hc_uniform(g) < 0.5 ? -1.0f : -0.0f;
  } else if (c == HC_UNIT) {
    *mu_s = hc_unit_or_any(g, 0.6);
    *nu = hc_unit_or_any(g, 0.6);
  }
}

/* One point of class c for inputs of kind in; n_index: the range of HI_INDEX. */
static inline void hard_case_point(hard_case_rng *g, hard_case_class c, hard_case_input in,
                                   const sf_atmosphere *atm, int n_index, float *p) {
  for (int k = 0; k < 8; ++k) p[k] = 0.0f;
  double z = atm->top_radius_km - atm->bottom_radius_km;
  switch (in) {
    case HI_RAY: case HI_RAY_T: case HI_RAY_T0T1: case HI_SKY: case HI_SKY_T: {
      int sky = in == HI_SKY || in == HI_SKY_T;
      hc_ray(g, c, atm, &p[0], &p[1]);
      int k = 2;
      if (sky) {
        hc_sun(g, c, atm, p[0], &p[2], &p[3]);
        k = 4;
      }
      if (in == HI_RAY || in == HI_SKY) break;
      double t = c == HC_SEGMENT ? hc_segment_distance(g, atm, p[0], p[1]) : hc_distance(g, z);
      if (in == HI_RAY_T0T1) {
        /* [t0, t1] around the stressed distance: a short piece ending or starting there, or empty */
        double other = hc_uniform(g) < 0.5 ? t * (1.0 - hc_uniform(g)) : t + hc_log_range(g, 1e-7, z);
        double pick = hc_uniform(g);
        if (c != HC_SEGMENT && pick < 0.5) other = hc_distance(g, z);
        if (c == HC_SEGMENT && pick < 0.1) other = t;
        p[k] = (float)fmin(t, other);
        p[k + 1] = (float)fmax(t, other);
      } else p[k] = (float)t;
      break;
    }
    case HI_GROUND: {
      double pick = hc_uniform(g);
      p[0] = (float)hc_uniform(g);
      p[1] = (float)hc_uniform(g);
      p[2] = (float)hc_range(g, -1.0, 1.0);
      if (c == HC_TANGENT)
        p[0] = pick < 0.3 ? 0.0f : pick < 0.4 ? -0.0f : pick < 0.8 ? hc_sign(g) * (float)hc_log_range(g, 1e-9, 1e-5)
                                                          : hc_sign(g) * 1.4e-45f * (float)(1 + (int)(8 * hc_uniform(g)));
      else if (c == HC_GROUND_DOWN) p[0] = pick < 0.2 ? -1.0f : -(float)hc_uniform(g);
      else if (c == HC_SUN_SHADOW) p[1] = pick < 0.2 ? -1.0f : pick < 0.3 ? -0.0f : -(float)hc_uniform(g);
      else if (c == HC_UNIT) {
        p[0] = hc_unit_or_any(g, 0.7);
        p[1] = hc_unit_or_any(g, 0.7);
        p[2] = pick < 0.3 ? (float)(1.0 - hc_log_range(g, 1e-8, 1e-3)) : hc_unit_or_any(g, 0.8);  /* at the sun */
      }
      break;
    }
    case HI_VEC4:
      for (int k = 0; k < 4; ++k) {
        if (c == HC_DEEP)   /* radiance -> 0: tiny and subnormal components, zeros */
          p[k] = hc_uniform(g) < 0.1 ? 0.0f : (float)hc_log_range(g, 1e-44, 1e-6);
        else p[k] = (float)hc_log_range(g, 1e-6, 1e2);
      }
      break;
    case HI_INDEX:
      p[0] = (float)((int)(hc_uniform(g) * (n_index + 4)) - 2);
      break;
    case HI_NONE:
      break;
  }
}

#endif
