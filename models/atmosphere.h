/* The physical description of an atmosphere (SPEC §4): a spherical shell
 * between bottom_radius_km and top_radius_km, filled with constituents whose
 * density profiles follow Bruneton 2017's layers. Plain value type: copy it,
 * no ownership. Lengths in km, coefficients in 1/km. */
#ifndef SKYFIT_MODELS_ATMOSPHERE_H
#define SKYFIT_MODELS_ATMOSPHERE_H

#include <stdint.h>

#define SF_MAX_CHANNELS 128     /* 360..830 nm at 5 nm is 95 wavelengths */
#define SF_MAX_CONSTITUENTS 8
/* 8 layers: the data's 9 km ozone distribution is 6 steps (4 had refused it) */
#define SF_MAX_LAYERS 8
/* every corner there can be: per layer its top and, on each side of the
 * layer's one stationary point, where it crosses 0 and 1 (the clamp);
 * fewer had dropped the rest of a many-layered atmosphere's corners */
#define SF_MAX_KINKS (SF_MAX_CONSTITUENTS * SF_MAX_LAYERS * 5)
#define SF_NAME_LEN 48
#define SF_KINK_MERGE_KM 1e-5

typedef struct sf_density_layer {
  double width_km;          /* this layer holds below the running sum of widths */
  double exp_term;
  double exp_scale_per_km;
  double linear_per_km;
  double constant;
} sf_density_layer;

typedef enum sf_phase_kind {
  SF_PHASE_NONE = 0,        /* purely absorbing constituent */
  SF_PHASE_RAYLEIGH,
  SF_PHASE_ISOTROPIC,
  SF_PHASE_HENYEY_GREENSTEIN,
  SF_PHASE_CORNETTE_SHANKS,
  SF_PHASE_DOUBLE_HENYEY_GREENSTEIN
} sf_phase_kind;

typedef struct sf_phase {
  sf_phase_kind kind;
  double g;                 /* henyey_greenstein, cornette_shanks */
  double g1, g2, f;         /* double_henyey_greenstein: (1-f)HG(g1) + f HG(g2) */
} sf_phase;

typedef struct sf_constituent {
  char name[SF_NAME_LEN];
  double scattering[SF_MAX_CHANNELS];   /* beta_s per channel, 1/km */
  double absorption[SF_MAX_CHANNELS];   /* beta_a per channel, 1/km */
  sf_phase phase;
  int n_layers;
  sf_density_layer layers[SF_MAX_LAYERS];
} sf_constituent;

typedef struct sf_atmosphere {
  char name[SF_NAME_LEN * 2];
  double bottom_radius_km;
  double top_radius_km;
  int n_channels;
  int spectral;                          /* 0: "rgb"; 1: wavelengths_nm */
  char channel_names[SF_MAX_CHANNELS][16]; /* "r","g","b" or "550" */
  double wavelengths_nm[SF_MAX_CHANNELS];  /* spectral only */
  double ground_albedo[SF_MAX_CHANNELS];
  double sun_irradiance[SF_MAX_CHANNELS];
  double sun_angular_radius_rad;
  int n_constituents;
  sf_constituent constituents[SF_MAX_CONSTITUENTS];
  /* Derived by sf_atmosphere_finalize: altitudes (km above the bottom) where
   * some density is not smooth (layer boundaries, clamp corners), sorted and
   * strictly inside (0, top - bottom). Quadrature splits rays there. */
  int n_kinks;
  double kink_altitudes_km[SF_MAX_KINKS];
} sf_atmosphere;

/* Density of one constituent at altitude h (km above the bottom radius),
 * Bruneton 2017: clamp(exp_term*exp(exp_scale*h) + linear*h + constant, 0, 1).
 * The constituent alone does not know the atmosphere's top: callers stop
 * their paths there (the last layer holds above it). */
double sf_constituent_density(const sf_constituent *c, double h_km);
/* One layer's unclamped value exp_term*exp(exp_scale*h) + linear*h + constant. */
double sf_density_layer_value(const sf_density_layer *l, double h_km);
double sf_atmosphere_thickness_km(const sf_atmosphere *atm);
/* Extinction coefficient beta_s + beta_a of constituent i in channel ch. */
static inline double sf_extinction(const sf_atmosphere *atm, int i, int ch) {
  return atm->constituents[i].scattering[ch] + atm->constituents[i].absorption[ch];
}
/* True if constituent i scatters light in any channel. */
int sf_constituent_scatters(const sf_constituent *c, int n_channels);
/* The number of constituents that scatter light: 0 for an atmosphere that
 * only absorbs (a black sky). */
int sf_atmosphere_scattering_count(const sf_atmosphere *atm);
/* Index of the constituent called name, or -1. */
int sf_atmosphere_find(const sf_atmosphere *atm, const char *name);

/* If the constituent's density is one pure exponential d0*exp(-h/H) with
 * 0 < d0 <= 1 over the whole atmosphere (no linear or constant part, so the
 * clamp never acts), stores H (km) and d0 and returns 1. The analytic
 * approximations (Chapman, Taylor, flat) exist only for such constituents. */
int sf_constituent_exponential(const sf_constituent *c, double *scale_height_km,
                               double *surface_density);
/* The number of such exponential constituents: 0 for an atmosphere the
 * analytic approximations cannot take. */
int sf_atmosphere_exponential_count(const sf_atmosphere *atm);

/* Computes the derived fields (kinks). Call after filling or changing the
 * description; the loaders do. */
void sf_atmosphere_finalize(sf_atmosphere *atm);

#endif
