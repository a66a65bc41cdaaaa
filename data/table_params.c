#include "data/table_params.h"

#include "models/ray_geometry.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

const char *sf_parameterization_name(sf_parameterization p) {
  return p == SF_PARAM_LEENMAN ? "leenman" : "bruneton";
}

int sf_parameterization_parse(const char *name, sf_parameterization *out, sf_error *err) {
  if (strcmp(name, "bruneton") == 0) *out = SF_PARAM_BRUNETON;
  else if (strcmp(name, "leenman") == 0) *out = SF_PARAM_LEENMAN;
  else
    return sf_fail(err, SF_ERR_INPUT, "parameterization: expected 'bruneton' or 'leenman', got '%s'", name);
  return SF_OK;
}

void sf_table_resolution_default(sf_table_resolution *res) {
  res->transmittance_mu = 256;
  res->transmittance_h = 64;
  res->scattering_h = 32;
  res->scattering_mu = 128;
  res->scattering_mu_s = 32;
  res->scattering_nu = 8;
  res->irradiance_mu_s = 64;
  res->irradiance_h = 16;
}

/* Reads count x count x ... (n counts) from *s, advancing it. */
static int parse_counts(const char **s, int n, long *out) {
  for (int k = 0; k < n; ++k) {
    if (k > 0) {
      if (**s != 'x' && **s != 'X') return -1;
      ++*s;
    }
    if (!(**s >= '0' && **s <= '9') && **s != '-' && **s != '+') return -1;
    char *end;
    errno = 0;
    long v = strtol(*s, &end, 10);
    if (end == *s) return -1;
    if (errno == ERANGE) v = v < 0 ? -1 : (long)SF_TABLE_MAX_AXIS_SIZE + 1;
    out[k] = v;
    *s = end;
  }
  return 0;
}

int sf_table_resolution_parse(const char *text, sf_table_resolution *res, sf_error *err) {
  long t[2], s[4];
  const char *p = text;
  if (parse_counts(&p, 2, t) != 0 || *p != ',' || (++p, parse_counts(&p, 4, s)) != 0 || *p != '\0')
    return sf_fail(err, SF_ERR_INPUT,
                   "--resolution: expected MUxH,HxMUxMU_SxNU (transmittance, then scattering; "
                   "e.g. 256x64,32x128x32x8), got '%s'", text);
  long all[6] = {t[0], t[1], s[0], s[1], s[2], s[3]};
  /* a negative count had been reported as "count -1" whatever was given */
  static const char *const axis[6] = {"transmittance mu", "transmittance h", "scattering h",
                                      "scattering mu",    "scattering mu_s", "scattering nu"};
  for (int k = 0; k < 6; ++k)
    if (all[k] < 0)
      return sf_fail(err, SF_ERR_INPUT, "--resolution: the %s count is negative in '%s' (counts are at least 2)",
                     axis[k], text);
  for (int k = 0; k < 6; ++k)
    if (all[k] < -1 || all[k] > SF_TABLE_MAX_AXIS_SIZE) all[k] = all[k] < 0 ? -1 : SF_TABLE_MAX_AXIS_SIZE + 1;
  sf_table_resolution r = *res;
  r.transmittance_mu = (int)all[0];
  r.transmittance_h = (int)all[1];
  r.scattering_h = (int)all[2];
  r.scattering_mu = (int)all[3];
  r.scattering_mu_s = (int)all[4];
  r.scattering_nu = (int)all[5];
  *res = r;
  return SF_OK;
}

int sf_table_resolution_check(const sf_table_resolution *res, sf_parameterization p, sf_error *err) {
  struct { const char *name; int v; } counts[] = {
      {"transmittance mu", res->transmittance_mu}, {"transmittance h", res->transmittance_h},
      {"scattering h", res->scattering_h},         {"scattering mu", res->scattering_mu},
      {"scattering mu_s", res->scattering_mu_s},   {"scattering nu", res->scattering_nu},
      {"irradiance mu_s", res->irradiance_mu_s},   {"irradiance h", res->irradiance_h}};
  for (size_t k = 0; k < sizeof counts / sizeof counts[0]; ++k) {
    if (counts[k].v < 2)
      return sf_fail(err, SF_ERR_INPUT, "resolution: %s count %d must be at least 2", counts[k].name, counts[k].v);
    if (counts[k].v > SF_TABLE_MAX_AXIS_SIZE)
      return sf_fail(err, SF_ERR_INPUT, "resolution: %s count exceeds the limit of %d", counts[k].name,
                     SF_TABLE_MAX_AXIS_SIZE);
  }
  if (p == SF_PARAM_BRUNETON && (res->scattering_mu % 2 != 0 || res->scattering_mu < 4))
    return sf_fail(err, SF_ERR_INPUT,
                   "resolution: bruneton scattering mu count %d must be even and at least 4 "
                   "(half for rays that hit the ground, half for the rest)", res->scattering_mu);
  return SF_OK;
}

void sf_table_params_make(sf_table_params *p, const sf_atmosphere *atm, sf_parameterization kind,
                          const sf_table_resolution *res) {
  p->kind = kind;
  p->bottom_radius_km = atm->bottom_radius_km;
  p->top_radius_km = atm->top_radius_km;
  p->mu_s_min = kind == SF_PARAM_BRUNETON ? SF_BRUNETON_MU_S_MIN : SF_LEENMAN_MU_S_MIN;
  p->res = *res;
  p->h_min_km = 0.0;
  p->h_max_km = atm->top_radius_km - atm->bottom_radius_km;
  p->mu_min = -1.0;
  p->mu_s_max = 1.0;
  p->sky_only = 0;
  p->restricted = 0;
}

int sf_table_params_restrict(sf_table_params *p, const sf_table_domain *d, sf_error *err) {
  double v[5] = {d->h_min_km, d->h_max_km, d->mu_min, d->mu_s_min, d->mu_s_max};
  for (int k = 0; k < 5; ++k)
    if (!isfinite(v[k])) return sf_fail(err, SF_ERR_INPUT, "table domain: a bound is not finite");
  double H = p->top_radius_km - p->bottom_radius_km;
  double h_lo = fmin(fmax(d->h_min_km, 0.0), H), h_hi = fmin(fmax(d->h_max_km, 0.0), H);
  if (!(d->h_min_km <= d->h_max_km))
    return sf_fail(err, SF_ERR_INPUT, "table domain: empty altitude range [%.17g, %.17g] km", d->h_min_km,
                   d->h_max_km);
  if (!(d->mu_min >= -1.0 && d->mu_min <= 1.0))
    return sf_fail(err, SF_ERR_INPUT, "table domain: lowest view cosine %.17g is outside [-1, 1]", d->mu_min);
  if (!(d->mu_s_min >= -1.0 && d->mu_s_max <= 1.0 && d->mu_s_min <= d->mu_s_max))
    return sf_fail(err, SF_ERR_INPUT, "table domain: sun cosine range [%.17g, %.17g] is empty or outside [-1, 1]",
                   d->mu_s_min, d->mu_s_max);
  p->h_min_km = h_lo;
  p->h_max_km = h_hi;
  p->mu_min = p->kind == SF_PARAM_LEENMAN ? d->mu_min : -1.0;
  p->mu_s_min = d->mu_s_min;
  p->mu_s_max = d->mu_s_max;
  p->sky_only = p->kind == SF_PARAM_BRUNETON && d->sky_only;
  p->restricted = 1;
  return SF_OK;
}

/* ---- Bruneton ------------------------------------------------------------ */

static double clamp01(double x) { return x < 0.0 ? 0.0 : (x > 1.0 ? 1.0 : x); }
static double clamp_cos(double x) { return x < -1.0 ? -1.0 : (x > 1.0 ? 1.0 : x); }
static double safe_sqrt(double x) { return sqrt(x > 0.0 ? x : 0.0); }

/* sqrt(Rt^2 - R^2) and rho = sqrt(r^2 - R^2) = sqrt(h (2R + h)), written
 * with altitudes so that they stay exact near the ground. */
static double horizon_length(double R, double Rt) { return safe_sqrt((Rt - R) * (Rt + R)); }
static double rho_of_h(double R, double h) { return safe_sqrt(h * (2.0 * R + h)); }

double sf_bruneton_x_from_h(double R, double Rt, double h) {
  return clamp01(rho_of_h(R, h) / horizon_length(R, Rt));
}

double sf_bruneton_h_from_x(double R, double Rt, double x) {
  double rho = horizon_length(R, Rt) * x;
  /* h = sqrt(R^2 + rho^2) - R without cancellation */
  return rho * rho / (R + sqrt(R * R + rho * rho));
}

/* Distance to the top sphere from radius r = R + h along mu (r <= Rt). */
static double distance_to_top(double R, double Rt, double h, double mu) {
  double r = R + h;
  double inside = (Rt - r) * (Rt + r);            /* >= 0 */
  double disc = inside + r * r * mu * mu;
  double root = safe_sqrt(disc);
  return mu > 0.0 ? inside / (r * mu + root) : root - r * mu;
}

/* Distance to the ground along a ray that hits it. */
static double distance_to_ground(double R, double h, double mu) {
  double r = R + h;
  double above = h * (2.0 * R + h);               /* r^2 - R^2 >= 0 */
  double root = safe_sqrt(r * r * mu * mu - above);
  double denom = -r * mu + root;
  return denom > 0.0 ? above / denom : 0.0;
}

double sf_bruneton_x_from_mu_top(double R, double Rt, double h, double mu) {
  double r = R + h, rho = rho_of_h(R, h), H = horizon_length(R, Rt);
  double d = distance_to_top(R, Rt, h, mu);
  double d_min = Rt - r, d_max = rho + H;
  return d_max > d_min ? clamp01((d - d_min) / (d_max - d_min)) : 0.0;
}

double sf_bruneton_mu_top_from_x(double R, double Rt, double h, double x) {
  double r = R + h, rho = rho_of_h(R, h), H = horizon_length(R, Rt);
  double d_min = Rt - r, d_max = rho + H;
  double d = d_min + x * (d_max - d_min);
  if (d <= 0.0) return 1.0;
  /* (H^2 - rho^2 - d^2) / (2 r d), with H^2 - rho^2 = Rt^2 - r^2 */
  return clamp_cos(((Rt - r) * (Rt + r) - d * d) / (2.0 * r * d));
}

double sf_bruneton_x_from_mu_ground(double R, double h, double mu) {
  double r = R + h, rho = rho_of_h(R, h);
  double d = distance_to_ground(R, h, mu);
  double d_min = r - R, d_max = rho;
  return d_max > d_min ? clamp01((d - d_min) / (d_max - d_min)) : 0.0;
}

double sf_bruneton_mu_ground_from_x(double R, double h, double x) {
  double r = R + h, rho = rho_of_h(R, h);
  double d_min = h, d_max = rho;
  double d = d_min + x * (d_max - d_min);
  if (d <= 0.0) return -1.0;
  return clamp_cos(-(rho * rho + d * d) / (2.0 * r * d));
}

/* a and A of Bruneton's mu_s mapping: the distance to the top of the sun
 * ray from the ground, normalised. */
static double mu_s_a(double R, double Rt, double mu_s) {
  double d = distance_to_top(R, Rt, 0.0, mu_s);
  double d_min = Rt - R, d_max = horizon_length(R, Rt);
  return (d - d_min) / (d_max - d_min);
}

double sf_bruneton_x_from_mu_s(double R, double Rt, double mu_s_min, double mu_s) {
  double a = mu_s_a(R, Rt, mu_s), A = mu_s_a(R, Rt, mu_s_min);
  double x = 1.0 - a / A;
  return clamp01((x > 0.0 ? x : 0.0) / (1.0 + a));
}

double sf_bruneton_mu_s_from_x(double R, double Rt, double mu_s_min, double x) {
  double A = mu_s_a(R, Rt, mu_s_min);
  double a = (A - x * A) / (1.0 + x * A);
  double d_min = Rt - R, H = horizon_length(R, Rt);
  double d = d_min + fmin(a, A) * (H - d_min);
  if (d <= 0.0) return 1.0;
  return clamp_cos((H * H - d * d) / (2.0 * R * d));
}

/* ---- positions ----------------------------------------------------------- */

static double clamp_pos(double pos, int n) { return pos < 0.0 ? 0.0 : (pos > n - 1 ? n - 1 : pos); }
static double unit_of(double pos, int n) { return clamp_pos(pos, n) / (double)(n - 1); }

static double leenman_h_from_x(const sf_table_params *p, double x) {
  return (p->top_radius_km - p->bottom_radius_km) * x * x;
}
static double leenman_x_from_h(const sf_table_params *p, double h) {
  double H = p->top_radius_km - p->bottom_radius_km;
  return clamp01(sqrt(h > 0.0 ? h / H : 0.0));
}

/* ---- the scattering tables' (possibly restricted) axes -------------------- */

/* rho at the ends of the h axis; the top uses horizon_length so that the
 * full domain maps exactly as sf_bruneton_x_from_h does. */
static double rho_at(const sf_table_params *p, double h) {
  double R = p->bottom_radius_km, Rt = p->top_radius_km;
  return h >= Rt - R ? horizon_length(R, Rt) : rho_of_h(R, h);
}

static double scattering_x_from_h(const sf_table_params *p, double h) {
  if (p->kind == SF_PARAM_BRUNETON) {
    double lo = rho_at(p, p->h_min_km), hi = rho_at(p, p->h_max_km);
    return hi > lo ? clamp01((rho_of_h(p->bottom_radius_km, h) - lo) / (hi - lo)) : 0.0;
  }
  double span = p->h_max_km - p->h_min_km, dh = h - p->h_min_km;
  return span > 0.0 ? clamp01(sqrt(dh > 0.0 ? dh / span : 0.0)) : 0.0;
}

static double scattering_h_from_x(const sf_table_params *p, double x) {
  if (p->kind == SF_PARAM_BRUNETON) {
    double R = p->bottom_radius_km;
    double lo = rho_at(p, p->h_min_km), hi = rho_at(p, p->h_max_km);
    if (!(hi > lo)) return p->h_min_km;
    double rho = lo + x * (hi - lo);
    return rho * rho / (R + sqrt(R * R + rho * rho));
  }
  return p->h_min_km + (p->h_max_km - p->h_min_km) * x * x;
}

/* Bruneton's mu_s mapping over [mu_s_min, mu_s_max]: his x (A at mu_s_min)
 * divided by its value at mu_s_max, which is left out when mu_s_max is 1
 * so that the full domain maps exactly as sf_bruneton_x_from_mu_s does. */
static double scattering_x_from_mu_s(const sf_table_params *p, double mu_s) {
  double R = p->bottom_radius_km, Rt = p->top_radius_km;
  if (p->kind == SF_PARAM_LEENMAN) {
    double span = p->mu_s_max - p->mu_s_min;
    return span > 0.0 ? clamp01((mu_s - p->mu_s_min) / span) : 0.0;
  }
  double x = sf_bruneton_x_from_mu_s(R, Rt, p->mu_s_min, mu_s);
  if (p->mu_s_max >= 1.0) return x;
  double x_max = sf_bruneton_x_from_mu_s(R, Rt, p->mu_s_min, p->mu_s_max);
  return x_max > 0.0 ? clamp01(x / x_max) : 0.0;
}

static double scattering_mu_s_from_x(const sf_table_params *p, double x) {
  double R = p->bottom_radius_km, Rt = p->top_radius_km;
  if (p->kind == SF_PARAM_LEENMAN) return p->mu_s_min + (p->mu_s_max - p->mu_s_min) * x;
  if (p->mu_s_max >= 1.0) return sf_bruneton_mu_s_from_x(R, Rt, p->mu_s_min, x);
  double x_max = sf_bruneton_x_from_mu_s(R, Rt, p->mu_s_min, p->mu_s_max);
  if (!(x_max > 0.0)) return p->mu_s_min;
  return fmin(sf_bruneton_mu_s_from_x(R, Rt, p->mu_s_min, x * x_max), p->mu_s_max);
}

void sf_params_transmittance_coord(const sf_table_params *p, const double *pos, double *h, double *mu) {
  double R = p->bottom_radius_km, Rt = p->top_radius_km;
  if (p->kind == SF_PARAM_BRUNETON) {
    *h = sf_bruneton_h_from_x(R, Rt, unit_of(pos[1], p->res.transmittance_h));
    *mu = sf_bruneton_mu_top_from_x(R, Rt, *h, unit_of(pos[0], p->res.transmittance_mu));
  } else {
    *h = leenman_h_from_x(p, unit_of(pos[0], p->res.transmittance_h));
    *mu = -1.0 + 2.0 * unit_of(pos[1], p->res.transmittance_mu);
  }
}

/* Tangent rays count as hitting, exactly as models/ray_geometry.h decides. */
static int ray_hits_ground(double R, double h, double mu) {
  return sf_ray_hits_sphere_from_above(R + h, mu, R);
}

int sf_params_transmittance_pos(const sf_table_params *p, double h, double mu, double *pos) {
  double R = p->bottom_radius_km, Rt = p->top_radius_km;
  int nm = p->res.transmittance_mu, nh = p->res.transmittance_h;
  if (p->kind == SF_PARAM_BRUNETON) {
    /* The table holds the rays to the top down to the horizon, the tangent
     * ray included: refuse only rays that pass below the ground (their
     * distance to the far side of the top sphere exceeds d_max). */
    if (ray_hits_ground(R, h, mu)) {
      double r = R + h, rho = rho_of_h(R, h), H = horizon_length(R, Rt);
      double d = distance_to_top(R, Rt, h, mu), d_min = Rt - r, d_max = rho + H;
      if (d > d_max + 1e-12 * (d_max - d_min)) return -1;
    }
    pos[1] = sf_bruneton_x_from_h(R, Rt, h) * (nh - 1);
    pos[0] = sf_bruneton_x_from_mu_top(R, Rt, h, mu) * (nm - 1);
  } else {
    pos[0] = leenman_x_from_h(p, h) * (nh - 1);
    pos[1] = clamp01(0.5 * (clamp_cos(mu) + 1.0)) * (nm - 1);
  }
  return 0;
}

void sf_params_scattering_coord(const sf_table_params *p, const double *pos, sf_scattering_coord *c) {
  double R = p->bottom_radius_km, Rt = p->top_radius_km;
  const sf_table_resolution *s = &p->res;
  if (p->kind == SF_PARAM_BRUNETON) {
    c->mu_s = scattering_mu_s_from_x(p, unit_of(pos[0], s->scattering_mu_s));
    c->nu = -1.0 + 2.0 * unit_of(pos[2], s->scattering_nu);
    c->h = scattering_h_from_x(p, unit_of(pos[3], s->scattering_h));
    if (p->sky_only) {
      c->mu = sf_bruneton_mu_top_from_x(R, Rt, c->h, unit_of(pos[1], s->scattering_mu));
      c->hits_ground = 0;
      return;
    }
    int half = s->scattering_mu / 2;
    double pm = clamp_pos(pos[1], s->scattering_mu);
    if (pm < half - 0.5) {
      double x = 1.0 - fmin(pm, half - 1.0) / (half - 1.0);
      c->mu = sf_bruneton_mu_ground_from_x(R, c->h, x);
      c->hits_ground = 1;
    } else {
      double x = (fmax(pm, (double)half) - half) / (half - 1.0);
      c->mu = sf_bruneton_mu_top_from_x(R, Rt, c->h, x);
      c->hits_ground = 0;
    }
  } else {
    c->h = scattering_h_from_x(p, unit_of(pos[0], s->scattering_h));
    c->mu = p->mu_min + (1.0 - p->mu_min) * unit_of(pos[1], s->scattering_mu);
    c->mu_s = scattering_mu_s_from_x(p, unit_of(pos[2], s->scattering_mu_s));
    c->nu = -1.0 + 2.0 * unit_of(pos[3], s->scattering_nu);
    c->hits_ground = ray_hits_ground(R, c->h, c->mu);
  }
}

void sf_params_scattering_pos(const sf_table_params *p, const sf_scattering_coord *c, double *pos) {
  double R = p->bottom_radius_km, Rt = p->top_radius_km;
  const sf_table_resolution *s = &p->res;
  double x_nu = clamp01(0.5 * (clamp_cos(c->nu) + 1.0));
  if (p->kind == SF_PARAM_BRUNETON) {
    int half = s->scattering_mu / 2;
    pos[0] = scattering_x_from_mu_s(p, c->mu_s) * (s->scattering_mu_s - 1);
    if (p->sky_only)
      pos[1] = sf_bruneton_x_from_mu_top(R, Rt, c->h, c->mu) * (s->scattering_mu - 1);
    else if (c->hits_ground)
      pos[1] = (half - 1) * (1.0 - sf_bruneton_x_from_mu_ground(R, c->h, c->mu));
    else
      pos[1] = half + (half - 1) * sf_bruneton_x_from_mu_top(R, Rt, c->h, c->mu);
    pos[2] = x_nu * (s->scattering_nu - 1);
    pos[3] = scattering_x_from_h(p, c->h) * (s->scattering_h - 1);
  } else {
    pos[0] = scattering_x_from_h(p, c->h) * (s->scattering_h - 1);
    pos[1] = clamp01((clamp_cos(c->mu) - p->mu_min) / (1.0 - p->mu_min)) * (s->scattering_mu - 1);
    pos[2] = scattering_x_from_mu_s(p, c->mu_s) * (s->scattering_mu_s - 1);
    pos[3] = x_nu * (s->scattering_nu - 1);
  }
}

void sf_params_irradiance_coord(const sf_table_params *p, const double *pos, double *h, double *mu_s) {
  *mu_s = -1.0 + 2.0 * unit_of(pos[0], p->res.irradiance_mu_s);
  *h = (p->top_radius_km - p->bottom_radius_km) * unit_of(pos[1], p->res.irradiance_h);
}

void sf_params_irradiance_pos(const sf_table_params *p, double h, double mu_s, double *pos) {
  double H = p->top_radius_km - p->bottom_radius_km;
  pos[0] = clamp01(0.5 * (clamp_cos(mu_s) + 1.0)) * (p->res.irradiance_mu_s - 1);
  pos[1] = clamp01(h / H) * (p->res.irradiance_h - 1);
}

/* ---- descriptions -------------------------------------------------------- */

static void set_axis(sf_table_axis *a, const char *name, int size, double min, double max,
                     const char *mapping) {
  snprintf(a->name, sizeof a->name, "%s", name);
  a->size = size;
  a->min = min;
  a->max = max;
  snprintf(a->mapping, sizeof a->mapping, "%s", mapping);
}

static int start_desc(const sf_table_params *p, const sf_atmosphere *atm, const char *quantity,
                      int n_axes, sf_table_desc *desc, sf_error *err) {
  memset(desc, 0, sizeof *desc);
  if (strlen(quantity) >= sizeof desc->quantity)
    return sf_fail(err, SF_ERR_INPUT, "table name '%s' is longer than %d characters", quantity,
                   (int)sizeof desc->quantity - 1);
  for (const char *c = quantity; *c; ++c)
    if (!((*c >= 'a' && *c <= 'z') || (*c >= 'A' && *c <= 'Z') || (*c >= '0' && *c <= '9') ||
          *c == '_' || *c == '-' || *c == '.'))
      return sf_fail(err, SF_ERR_INPUT, "table name '%s' may only use the characters [A-Za-z0-9_.-]",
                     quantity);
  snprintf(desc->quantity, sizeof desc->quantity, "%s", quantity);
  snprintf(desc->parameterization, sizeof desc->parameterization, "%s", sf_parameterization_name(p->kind));
  desc->n_axes = n_axes;
  sf_table_desc_set_channels(desc, atm);
  return SF_OK;
}

int sf_params_transmittance_desc(const sf_table_params *p, const sf_atmosphere *atm,
                                 sf_table_desc *desc, sf_error *err) {
  if (start_desc(p, atm, "transmittance", 2, desc, err)) return SF_ERR_INPUT;
  double H = p->top_radius_km - p->bottom_radius_km;
  if (p->kind == SF_PARAM_BRUNETON) {
    set_axis(&desc->axes[0], "mu", p->res.transmittance_mu, -1.0, 1.0, "bruneton_mu_top");
    set_axis(&desc->axes[1], "h_km", p->res.transmittance_h, 0.0, H, "bruneton_rho");
  } else {
    set_axis(&desc->axes[0], "h_km", p->res.transmittance_h, 0.0, H, "squared");
    set_axis(&desc->axes[1], "mu", p->res.transmittance_mu, -1.0, 1.0, "linear");
  }
  return SF_OK;
}

int sf_params_scattering_desc(const sf_table_params *p, const sf_atmosphere *atm,
                              const char *quantity, sf_table_desc *desc, sf_error *err) {
  if (start_desc(p, atm, quantity, 4, desc, err)) return SF_ERR_INPUT;
  const sf_table_resolution *s = &p->res;
  double h0 = p->h_min_km, h1 = p->h_max_km;
  if (p->kind == SF_PARAM_BRUNETON) {
    set_axis(&desc->axes[0], "mu_s", s->scattering_mu_s, p->mu_s_min, p->mu_s_max, "bruneton_mu_s");
    /* sky only: every sample a ray to the top, straight up to the horizon */
    set_axis(&desc->axes[1], "mu", s->scattering_mu, -1.0, 1.0,
             p->sky_only ? "bruneton_mu_top" : "bruneton_mu_split");
    set_axis(&desc->axes[2], "nu", s->scattering_nu, -1.0, 1.0, "linear");
    set_axis(&desc->axes[3], "h_km", s->scattering_h, h0, h1, "bruneton_rho");
  } else {
    set_axis(&desc->axes[0], "h_km", s->scattering_h, h0, h1, "squared");
    set_axis(&desc->axes[1], "mu", s->scattering_mu, p->mu_min, 1.0, "linear");
    set_axis(&desc->axes[2], "mu_s", s->scattering_mu_s, p->mu_s_min, p->mu_s_max, "linear");
    set_axis(&desc->axes[3], "nu", s->scattering_nu, -1.0, 1.0, "linear");
  }
  return SF_OK;
}

int sf_params_irradiance_desc(const sf_table_params *p, const sf_atmosphere *atm,
                              sf_table_desc *desc, sf_error *err) {
  if (start_desc(p, atm, "irradiance", 2, desc, err)) return SF_ERR_INPUT;
  set_axis(&desc->axes[0], "mu_s", p->res.irradiance_mu_s, -1.0, 1.0, "linear");
  set_axis(&desc->axes[1], "h_km", p->res.irradiance_h, 0.0, p->top_radius_km - p->bottom_radius_km,
           "linear");
  return SF_OK;
}
