/* Where the samples of the reference tables lie (SPEC §6): the two
 * parameterisations of transmittance over (h, mu) and scattering over
 * (h, mu, mu_s, nu), both ways between a table position and the physical
 * coordinates.
 *
 * Positions are fractional indices: pos = 2.5 on an axis lies half-way
 * between samples 2 and 3, so sample i sits exactly at pos = i and the end
 * samples sit exactly on the ends of the range (a table is a grid of
 * samples, not of texels). A GPU texture coordinate is uv = (pos + 0.5)/n.
 *
 * Bruneton (Bruneton 2017, "precomputed_atmospheric_scattering"), per unit
 * coordinate x in [0, 1] (pos = x (n - 1)):
 *   h:    x = rho / H, rho = sqrt(r^2 - R^2), H = sqrt(Rt^2 - R^2): samples
 *         crowd near the ground;
 *   mu (transmittance, rays to the top): x = (d - d_min) / (d_max - d_min)
 *         with d the distance to the top, d_min = Rt - r, d_max = rho + H;
 *         covers mu from 1 down to the horizon;
 *   mu (scattering): two halves of n/2 samples. Rays that hit the ground
 *         occupy pos 0..n/2-1 (the horizon at 0, straight down at n/2-1),
 *         x = (d - (r - R)) / (rho - (r - R)) with d the distance to the
 *         ground, pos = (n/2 - 1)(1 - x); rays to the top occupy n/2..n-1
 *         (straight up at n/2, the horizon at n-1), x as for transmittance,
 *         pos = n/2 + (n/2 - 1) x. A lookup never mixes the halves, so the
 *         jump at the horizon between sky and ground stays sharp;
 *   mu_s: x = max(1 - a/A, 0) / (1 + a), a = (d - d_min)/(d_max - d_min)
 *         for the sun ray from the ground (d_min = Rt - R, d_max = H) and A
 *         the same at mu_s_min: covers [mu_s_min, 1];
 *   nu:   x = (nu + 1) / 2.
 * Axis order (axes[0] fastest) follows Bruneton's textures: transmittance
 * (mu, h), 256 x 64 by default; scattering (mu_s, mu, nu, h), so that the
 * image tiling of data/table.h (x = i0 + n0 i2, y = i1 + n1 i3) is exactly
 * his 3D texture (x = mu_s + MU_S_SIZE * nu, y = mu) with its r slices
 * stacked vertically.
 *
 * Leenman (seed 000 §9.1, Figures 5-6): uniform in
 *   h:    x = sqrt(h / (Rt - R)), i.e. h = (Rt - R) x^2: "the square gives
 *         more samples to the lower altitudes" — the sample coordinate
 *         squared is the normalised height;
 *   mu = cos(view zenith) in [-1, 1]; mu_s in [cos 100°, 1] ("the light angle
 *   is limited to be between 0 and 100 degrees"); nu = cos gamma in [-1, 1].
 * Axis order: transmittance (h, mu) as Figure 5 (x = h, y = cos view);
 * scattering (h, mu, mu_s, nu): tiles of (h, mu) arranged by mu_s along x
 * and nu along y, as Figure 6.
 *
 * Transmittance entries hold the ray to the top (Bruneton: only rays above
 * the horizon are stored) or to the ground or the top, whichever comes first
 * (Leenman, the whole mu range). Scattering entries integrate along the ray
 * to its end: the ground for the ground half (Bruneton) or where the ray
 * hits it (Leenman), else the top. A nu outside the range mu and mu_s allow
 * is clamped into it (SPEC §3) when the entry is computed. */
#ifndef SKYFIT_DATA_TABLE_PARAMS_H
#define SKYFIT_DATA_TABLE_PARAMS_H

#include <stddef.h>

#include "data/table.h"
#include "models/atmosphere.h"
#include "util/error.h"

typedef enum sf_parameterization { SF_PARAM_BRUNETON = 0, SF_PARAM_LEENMAN = 1 } sf_parameterization;

/* "bruneton" / "leenman". */
const char *sf_parameterization_name(sf_parameterization p);
/* Returns 0 and sets *out, or SF_ERR_INPUT naming the accepted values. */
int sf_parameterization_parse(const char *name, sf_parameterization *out, sf_error *err);

/* Sample counts. Defaults: transmittance 256 (mu) x 64 (h); scattering
 * 32 (h) x 128 (mu) x 32 (mu_s) x 8 (nu); irradiance 64 (mu_s) x 16 (h). */
typedef struct sf_table_resolution {
  int transmittance_mu, transmittance_h;
  int scattering_h, scattering_mu, scattering_mu_s, scattering_nu;
  int irradiance_mu_s, irradiance_h;
} sf_table_resolution;

void sf_table_resolution_default(sf_table_resolution *res);
/* "MUxH,HxMUxMU_SxNU" (e.g. "256x64,32x128x32x8"): transmittance then
 * scattering counts; the irradiance table keeps its default. SF_ERR_INPUT
 * with the offending text otherwise; *res untouched on failure. */
int sf_table_resolution_parse(const char *text, sf_table_resolution *res, sf_error *err);
/* Every count >= 2 and <= SF_TABLE_MAX_AXIS_SIZE; the Bruneton scattering
 * mu count even and >= 4. SF_ERR_INPUT naming the count otherwise. */
int sf_table_resolution_check(const sf_table_resolution *res, sf_parameterization p, sf_error *err);

#define SF_TABLE_MAX_AXIS_SIZE 65536
/* Lowest sun cosines covered: Bruneton's demo uses a maximum sun zenith
 * angle of 102° (his half-precision setting); Leenman limits it to 100°. */
#define SF_BRUNETON_MU_S_MIN (-0.20791169081775934)  /* cos 102° */
#define SF_LEENMAN_MU_S_MIN (-0.17364817766693033)   /* cos 100° */

/* The part of (h, mu, mu_s) a scene needs (SPEC §5, models/scene_file.h
 * sf_scene_get_domain): the scattering tables may cover only it. */
typedef struct sf_table_domain {
  double h_min_km, h_max_km;   /* viewer altitudes, clamped into [0, Rt - R] */
  double mu_min;               /* lowest view cosine (Leenman's linear mu axis) */
  double mu_s_min, mu_s_max;   /* sun cosines, within [-1, 1] */
  int sky_only;                /* only rays above the horizon are asked for
                                  (view "above_horizon"): Bruneton's mu axis
                                  keeps its sky half only */
} sf_table_domain;

typedef struct sf_table_params {
  sf_parameterization kind;
  double bottom_radius_km, top_radius_km;
  double mu_s_min;
  sf_table_resolution res;
  /* The scattering tables' domain. sf_table_params_make sets the full one:
   * h in [0, Rt - R], mu in [-1, 1] (both Bruneton halves), mu_s in
   * [mu_s_min, 1]; sf_table_params_restrict narrows it. A restricted axis
   * keeps its mapping, taken over the narrower range: Bruneton h is linear
   * in rho between rho(h_min) and rho(h_max); Bruneton mu_s is his mapping
   * with A at mu_s_min, rescaled so that mu_s_max sits at x = 1; Leenman h is
   * h_min + (h_max - h_min) x^2, Leenman mu and mu_s linear over their
   * ranges. The transmittance and irradiance tables always cover the full
   * domain: ratios of transmittances (segments, rays to the ground) and the
   * ground lit from anywhere need every altitude and sun angle. */
  double h_min_km, h_max_km;
  double mu_min;               /* Leenman only */
  double mu_s_max;
  int sky_only;                /* Bruneton only */
  int restricted;              /* 1 after sf_table_params_restrict */
} sf_table_params;

void sf_table_params_make(sf_table_params *p, const sf_atmosphere *atm, sf_parameterization kind,
                          const sf_table_resolution *res);

/* Narrows p's scattering domain to d (altitudes clamped into the
 * atmosphere). SF_ERR_INPUT naming the range when d is not finite, a range
 * is empty (min > max) or lies outside [-1, 1]. A range of one value is
 * valid: every sample of that axis then holds the same point. */
int sf_table_params_restrict(sf_table_params *p, const sf_table_domain *d, sf_error *err);

/* A point of the scattering tables: viewer altitude h (km above the bottom),
 * view, sun and view-sun cosines, and whether the ray ends on the ground. */
typedef struct sf_scattering_coord {
  double h, mu, mu_s, nu;
  int hits_ground;
} sf_scattering_coord;

/* ---- Bruneton's unit coordinates (each in [0, 1]) ---------------------- */
double sf_bruneton_x_from_h(double R, double Rt, double h);
double sf_bruneton_h_from_x(double R, double Rt, double x);
/* Rays to the top (transmittance, and the sky half of scattering). */
double sf_bruneton_x_from_mu_top(double R, double Rt, double h, double mu);
double sf_bruneton_mu_top_from_x(double R, double Rt, double h, double x);
/* Rays to the ground (the ground half of scattering); x = 0 straight down. */
double sf_bruneton_x_from_mu_ground(double R, double h, double mu);
double sf_bruneton_mu_ground_from_x(double R, double h, double x);
double sf_bruneton_x_from_mu_s(double R, double Rt, double mu_s_min, double mu_s);
double sf_bruneton_mu_s_from_x(double R, double Rt, double mu_s_min, double x);

/* ---- table positions <-> coordinates ------------------------------------ */
/* GPU texture coordinate of a position on an axis of n samples, and back. */
static inline double sf_params_uv_of_pos(double pos, int n) { return (pos + 0.5) / n; }
static inline double sf_params_pos_of_uv(double uv, int n) { return uv * n - 0.5; }

/* Transmittance: pos[0..1] in axis order. */
void sf_params_transmittance_coord(const sf_table_params *p, const double *pos, double *h, double *mu);
/* Returns 0 and fills pos (clamped into the table) or -1 when the table
 * does not hold the ray: Bruneton, a ray that hits the ground. */
int sf_params_transmittance_pos(const sf_table_params *p, double h, double mu, double *pos);

/* Scattering: pos[0..3] in axis order. The nu returned is the grid's own
 * (not clamped). */
void sf_params_scattering_coord(const sf_table_params *p, const double *pos, sf_scattering_coord *c);
/* Inverse of the above; each position clamped into its axis (and, for
 * Bruneton's mu, into the half that c->hits_ground selects). */
void sf_params_scattering_pos(const sf_table_params *p, const sf_scattering_coord *c, double *pos);

/* Irradiance (Bruneton's layout for both: axes (mu_s, h), linear in mu_s
 * over [-1, 1] and in h over [0, Rt - R]). */
void sf_params_irradiance_coord(const sf_table_params *p, const double *pos, double *h, double *mu_s);
void sf_params_irradiance_pos(const sf_table_params *p, double h, double mu_s, double *pos);

/* Table descriptions (axes, sizes, mappings, channels of atm) for quantity.
 * SF_ERR_INPUT if quantity is not a valid table name. */
int sf_params_transmittance_desc(const sf_table_params *p, const sf_atmosphere *atm,
                                 sf_table_desc *desc, sf_error *err);
int sf_params_scattering_desc(const sf_table_params *p, const sf_atmosphere *atm,
                              const char *quantity, sf_table_desc *desc, sf_error *err);
int sf_params_irradiance_desc(const sf_table_params *p, const sf_atmosphere *atm,
                              sf_table_desc *desc, sf_error *err);

#endif
