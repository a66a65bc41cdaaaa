/* The neural sky (SPEC §7.4-7.5, seed 000 §9.6): transmittance and
 * scattering evaluated from the networks of models/mlp.h, in double and in
 * float32 (the float path is what emitted shaders must do, operation for
 * operation).
 *
 * Geometry: R = bottom radius, Rt = top radius, viewer at radius r = R + h
 * looking along mu; along the ray, at distance d,
 *   r_d = sqrt(r^2 + d^2 + 2 r mu d),  mu_d = (r mu + d) / r_d,
 *   mu_s_d = (r mu_s + d nu) / r_d.
 * A viewer above Rt is first moved to where its ray enters the atmosphere
 * (seed 000 §9.6.3: "any viewer that is outside the atmosphere is moved to
 * the top atmosphere boundary"); a ray that never enters sees T = 1, S = 0.
 *
 * Inputs of every network: x = ((value - offset) * scale) per input, values
 * sqrt(h) ("sqrt_h_km"), mu, and for scattering mu_s, nu (nu clamped into
 * what mu and mu_s allow, SPEC §3).
 *
 * The transmittance network may instead take Bruneton's horizon-aware
 * coordinates (Bruneton 2017, GetTransmittanceTextureUvFromRMu, without the
 * texel centring; input names "x_r", "x_mu" in the weights file, so files
 * naming "sqrt_h_km", "mu" keep the old mapping):
 *   x_r  = rho / H,                rho = sqrt(r^2 - R^2) = sqrt(h (2R + h)),
 *                                  H = sqrt(Rt^2 - R^2);
 *   x_mu = (d - d_min) / (d_max - d_min),  d the distance to the top along
 *          mu, d_min = Rt - r (zenith), d_max = rho + H (the ray tangent to
 *          the ground), clamped to [0, 1].
 * T_top is smooth over the unit square there: the horizon is the edge
 * x_mu = 1 at every altitude, where in (sqrt h, mu) it is a curve. Written
 * without cancellation for float32: r^2 - R^2 = h (2R + h),
 * Rt^2 - r^2 = (h_top - h)(Rt + r), and for mu > 0
 * d = (Rt^2 - r^2) / (r mu + sqrt(Rt^2 - r^2 + r^2 mu^2)).
 *
 * Transmittance network (target "transmittance_top"): outputs T_top(h, mu)
 * per channel, the transmittance of the ray from altitude h along mu to the
 * TOP boundary, trained only for rays that do not hit the ground (mu at or
 * above the horizon cosine -sqrt(1 - (R/r)^2)). With the exp_neg output
 * (default) the last layer's pre-activation is the optical depth
 * tau_top = -log T_top, and every ratio below is computed as
 * exp(-(tau_a - tau_b)) (no division of two tiny numbers, SPEC §10), the
 * difference tau_a - tau_b carried through the network beside the two
 * forward passes rather than subtracted (models/mlp_sky_impl.inc
 * t_depth_diff: at tau ~ 600 float32 loses the segment in the rounding of
 * the two depths); with another output the ratio T_a / max(T_b, 1e-30) is clamped to [0, 1].
 *   Full ray (to the ground or the top, whichever comes first):
 *     no ground hit:  T = T_top(h, mu)
 *     ground hit at distance d_g (mu_g = mu at the ground, < 0), eq. 43
 *     with reversed rays (seed 000 §9.6.3): both rays point up,
 *       T = T_top(0, -mu_g) / T_top(h, -mu).
 *   Segment from the viewer to distance d, cut where the ray meets the
 *   ground (eq. 43, Bruneton 2017
 *   GetTransmittance): if the viewer's ray hits the ground, or the
 *   segment ends before the line's closest point (mu_d < 0)
 *       T = T_top(h_d, -mu_d) / T_top(h, -mu)          (reversed)
 *     else
 *       T = T_top(h, mu) / T_top(h_d, mu_d).
 *   (Forward, a descending segment's two rays both pass the closest point,
 *   long and dark, and the network's errors on them do not cancel. The
 *   two forms meet at the closest point up to the network's error there:
 *   a seam of at most 0.011 in T for weights/default, h 95 km, mu -0.138.)
 *
 * Scattering network: outputs the light scattered towards the viewer along
 * the ray to its end (the ground if it hits it, else the top), as in the
 * reference tables (data/table_params.h), from a sun of irradiance 1:
 *   target "radiance" (seed 000 §9.6.2): n_channels outputs = the sky
 *     radiance, phase functions included;
 *   target "separate" (default): (n_single + 1) * n_channels outputs, the
 *     single scattering of each scattering constituent WITHOUT its phase
 *     function (Bruneton's convention), then multiple scattering; the
 *     radiance is   L_c = sum_k P_k(nu) S_k,c + M_c.
 *     Phase functions thus stay exact (the Mie halo is not asked of the
 *     network, seed 000 §12.1.6), and because every term is an integral
 *     along the ray, eq. 44 applies to each of them.
 *   Horizon split (optional, params "ground_W0", ... in the weights file):
 *     a second network of the same layers for the rays that end on the
 *     ground, the first then only for rays to the top. The radiance steps
 *     at the horizon (Bruneton keeps the two kinds of ray in separate
 *     halves of his table); one network must smear that step, two need
 *     not, and a ray is only ever one kind, so a pixel still costs one
 *     network (bench/mlp_accuracy.sh: 3.4-4.8x lower MSE for 4-8-8-9). A ray
 *     ends on the ground when mu < 0 and -h (R + r) + (r mu)^2 >= 0 (the
 *     discriminant of models/ray_geometry.h, as the transmittance's
 *     reversed rays test it); from h = 0 such a ray has length 0:
 *     radiance exactly 0.
 *   Sky radiance of a full ray: L(h, mu, mu_s, nu) directly.
 *   Segment from the viewer to distance d (aerial perspective), eq. 44:
 *       S = S(h, mu, mu_s, nu) - T(viewer -> d) * S(h_d, mu_d, mu_s_d, nu)
 *     with T the transmittance segment above (reversed rays when the ray
 *     hits the ground, as the seed notes, or the segment ends before the
 *     line's closest point), clamped at 0. A segment reaching the top's
 *     exit is the full ray S(h, mu, mu_s, nu): the network's radiance of
 *     the empty ray there is not 0, so the segment steps by T S(exit) as
 *     its end reaches the exit (median 5.8e-5, at most 1.2e-3 for
 *     weights/default; README, limitations): the network's error, which
 *     continuity would move onto every segment past the top instead.
 * Multiply by the atmosphere's sun irradiance per channel. */
#ifndef SKYFIT_MODELS_MLP_SKY_H
#define SKYFIT_MODELS_MLP_SKY_H

#include "models/atmosphere.h"
#include "models/mlp.h"
#include "models/weights_file.h"
#include "util/error.h"

typedef enum sf_mlp_target {
  SF_MLP_TARGET_TRANSMITTANCE_TOP = 0,
  SF_MLP_TARGET_RADIANCE,
  SF_MLP_TARGET_SEPARATE
} sf_mlp_target;

/* "transmittance_top", "radiance", "separate". */
const char *sf_mlp_target_name(sf_mlp_target t);
int sf_mlp_target_parse(const char *name, sf_mlp_target *out);

/* What the transmittance network's two inputs are (above). */
typedef enum sf_mlp_input_map {
  SF_MLP_INPUTS_SQRT_H_MU = 0,   /* "sqrt_h_km", "mu" (every scattering network) */
  SF_MLP_INPUTS_BRUNETON         /* "x_r", "x_mu" */
} sf_mlp_input_map;

/* "sqrt_h_mu" / "bruneton" (command-line names). */
const char *sf_mlp_input_map_name(sf_mlp_input_map m);
int sf_mlp_input_map_parse(const char *name, sf_mlp_input_map *out);
/* The weights-file names of input k (0, 1) under the mapping. */
const char *sf_mlp_input_map_input_name(sf_mlp_input_map m, int k);

/* Bruneton's coordinates (x_r, x_mu) above, in double, for the data sets;
 * h is clamped to [0, Rt - R], mu to [-1, 1]. */
void sf_mlp_bruneton_coords(double bottom_radius_km, double top_radius_km, double h_km, double mu, double *x_r,
                            double *x_mu);

/* Its inverse (Bruneton 2017 GetRMuFromTransmittanceTextureUv): the (h, mu)
 * of (x_r, x_mu) in [0, 1]^2, for metrics on normalised data sets. */
void sf_mlp_bruneton_inverse(double bottom_radius_km, double top_radius_km, double x_r, double x_mu, double *h_km,
                             double *mu);

/* Brightness normalisation of a scattering network (optional, per
 * network; `skyfit fit mlp-scattering --normalise brightness`): the network
 * was trained on targets y / exp(b), so its outputs are multiplied back by
 * exp(b). exp(b) is the sky's brightness at that altitude and sun elevation
 * (fit/output_norm.h fits it), so the loss weighs every situation by its
 * own brightness: the dawn sky is hundreds of times dimmer than noon's and
 * plain MSE does not see it. With u, v the network's normalised inputs 0
 * (sqrt h) and 2 (mu_s), A = degree_h, C = degree_mu_s,
 *   P(u, v) = sum_{a<=A, c<=C} coef[a (C+1) + c] u^a v^c   (Horner in v, then u)
 * is fitted on [-1, 1]^2, and outside it a polynomial of degree 6 is
 * anything, so
 *   b = min(P(u', v'), cap) + max(S(u'), 0) * min(v + 1, 0),
 *       u', v' = u, v clamped to [-1, 1],
 *   S(u) = dP/dv (u, -1) = sum_a edge_slope[a] u^a    (Horner in u):
 * a sun below the domain's lowest (v < -1; the night side seen from space)
 * dims on at the rate it dims at that edge, never brighter, and the
 * network itself sees it at the edge (its input v clamped to -1): it was
 * never trained there, and of 12 networks measured one grew there faster
 * than the brightness fell (space view RMSE 3.6; 0.005 clamped); a sun
 * above the highest keeps its brightness. The cap (fit/output_norm.h)
 * leaves the bright situations, those within a factor e^cap_below of the
 * brightest, weighed among themselves as raw targets are, and lifts only
 * the dimmer ones: without it the noon views' error grew up to 2.4x.
 * Without has_cap (a file without params.norm_cap) there is none. The
 * model evaluates this operation for operation in double and float32, and
 * so does the emitted code. */
#define SF_MLP_NORM_MAX_DEGREE 7
/* |cap| must be below this: exp(cap) stays a normal float32 */
#define SF_MLP_NORM_CAP_LIMIT 80.0
#define SF_MLP_NORM_MAX_COEFS ((SF_MLP_NORM_MAX_DEGREE + 1) * (SF_MLP_NORM_MAX_DEGREE + 1))
typedef struct sf_mlp_output_norm {
  int active;                   /* 0: outputs as the network gives them */
  int degree_h, degree_mu_s;
  double coef[SF_MLP_NORM_MAX_COEFS];
  int has_cap;
  double cap;                   /* upper bound of P, if has_cap */
  /* derived by sf_mlp_output_norm_finish: */
  double edge_slope[SF_MLP_NORM_MAX_DEGREE + 1];
  float coef_f[SF_MLP_NORM_MAX_COEFS], edge_slope_f[SF_MLP_NORM_MAX_DEGREE + 1], cap_f;
} sf_mlp_output_norm;

/* Fills the derived members (float32 copies, edge_slope) from degree_h,
 * degree_mu_s, coef and cap, and sets active. */
void sf_mlp_output_norm_finish(sf_mlp_output_norm *n);
/* b(u, v) above, in double. */
double sf_mlp_output_norm_log_brightness(const sf_mlp_output_norm *n, double u, double v);

/* A network with what its inputs and outputs mean. */
typedef struct sf_mlp_sky {
  sf_mlp net;
  sf_mlp_f net_f;
  sf_mlp_target target;
  int n_inputs;
  sf_mlp_input_map input_map;   /* transmittance network only; sf_mlp_sky_make sets SQRT_H_MU */
  double offset[4], scale[4];   /* per input, see above */
  float offset_f[4], scale_f[4];
  double bottom_radius_km, top_radius_km;
  int n_channels;
  int n_single;                 /* separate: scattering constituents, then multiple */
  sf_phase phases[SF_MAX_CONSTITUENTS];
  int horizon_split;            /* scattering: net_ground for rays ending on the ground (above) */
  sf_mlp net_ground;
  sf_mlp_f net_ground_f;
  sf_mlp_output_norm norm, norm_ground;   /* scattering: per network (above) */
} sf_mlp_sky;

/* Builds the model from a trained network (owned by the model afterwards:
 * net is moved in). For target separate, phase_constituent[k] names the
 * atmosphere constituent of single-scattering output block k. */
int sf_mlp_sky_make(sf_mlp_sky *m, sf_mlp *net, sf_mlp_target target, const sf_atmosphere *atm,
                    const double *offset, const double *scale, int n_single, const int *phase_constituent,
                    sf_error *err);
/* Gives a scattering model its ground-ray network (horizon split, above;
 * moved in like sf_mlp_sky_make's): same layers and activations as m->net,
 * SF_ERR_INPUT otherwise (net freed). */
int sf_mlp_sky_set_ground_net(sf_mlp_sky *m, sf_mlp *net, sf_error *err);
/* Gives network 0 (sky) or 1 (ground) of a scattering model its brightness
 * normalisation (copied; its float32 values are made here). SF_ERR_INPUT if
 * the degrees exceed SF_MLP_NORM_MAX_DEGREE or the network is missing. */
int sf_mlp_sky_set_output_norm(sf_mlp_sky *m, int ground, const sf_mlp_output_norm *norm, sf_error *err);
/* Adds the normalisations to a weights document being written: params
 * norm_coef, an (A+1) x (C+1) array, and norm_cap, one value if it has a
 * cap (ground_norm_coef, ground_norm_cap for the ground network), each only
 * where the network has one. */
int sf_mlp_sky_add_norms_to_weights(cJSON *doc, const sf_mlp_sky *m);
/* Whether the model's ray from altitude h_km along mu counts as ending on
 * the ground (the horizon split's test above), double and float32. */
int sf_mlp_ray_ends_on_ground(double bottom_radius_km, double h_km, double mu);
int sf_mlp_ray_ends_on_ground_f(float bottom_radius_km, float h_km, float mu);
/* Loads "mlp-transmittance" or "mlp-scattering" weights (SPEC §8); a
 * training.target that does not fit the file's model (transmittance_top
 * for mlp-transmittance, radiance or separate for mlp-scattering) is
 * SF_ERR_INPUT. */
int sf_mlp_sky_load(const char *path, sf_mlp_sky *m, sf_error *err);
int sf_mlp_sky_from_weights(const sf_weights *w, sf_mlp_sky *m, sf_error *err);
void sf_mlp_sky_free(sf_mlp_sky *m);

/* Number of channels of transmittance / radiance results. */
static inline int sf_mlp_sky_channels(const sf_mlp_sky *m) { return m->n_channels; }

/* ---- double ---- */
/* Network output T_top(h, mu) (no ground handling; for tests and fitting). */
void sf_mlp_transmittance_top(const sf_mlp_sky *t, double h_km, double mu, double *T);
/* Full ray and segment transmittance (above). */
void sf_mlp_transmittance(const sf_mlp_sky *t, double h_km, double mu, double *T);
void sf_mlp_transmittance_segment(const sf_mlp_sky *t, double h_km, double mu, double d_km, double *T);
/* Sky radiance of the full ray (no sun disc, no ground), and of a segment
 * (needs the transmittance model for eq. 44). */
void sf_mlp_scattering(const sf_mlp_sky *s, double h_km, double mu, double mu_s, double nu, double *L);
void sf_mlp_scattering_segment(const sf_mlp_sky *s, const sf_mlp_sky *t, double h_km, double mu,
                               double mu_s, double nu, double d_km, double *L);

/* ---- float32, operation for operation as the shader ---- */
void sf_mlp_transmittance_top_f(const sf_mlp_sky *t, float h_km, float mu, float *T);
void sf_mlp_transmittance_f(const sf_mlp_sky *t, float h_km, float mu, float *T);
void sf_mlp_transmittance_segment_f(const sf_mlp_sky *t, float h_km, float mu, float d_km, float *T);
void sf_mlp_scattering_f(const sf_mlp_sky *s, float h_km, float mu, float mu_s, float nu, float *L);
void sf_mlp_scattering_segment_f(const sf_mlp_sky *s, const sf_mlp_sky *t, float h_km, float mu, float mu_s,
                                 float nu, float d_km, float *L);

#endif
