#include "models/mlp_sky.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "models/emitted_float.h"
#include "models/phase.h"
#include "models/ray_geometry.h"
#include "models/single_scattering.h"

static const char *const target_names[] = {"transmittance_top", "radiance", "separate"};

const char *sf_mlp_target_name(sf_mlp_target t) { return (unsigned)t < 3u ? target_names[t] : "?"; }

int sf_mlp_target_parse(const char *name, sf_mlp_target *out) {
  for (int k = 0; k < 3; ++k)
    if (strcmp(name, target_names[k]) == 0) {
      *out = (sf_mlp_target)k;
      return 0;
    }
  return -1;
}

/* The network in double; depth = 1 gives the last layer's pre-activation. */
static void net_forward_d(const sf_mlp_sky *m, const double *x, double *out, int depth) {
  sf_mlp_shape s = m->net.shape;
  if (depth) s.output = SF_ACT_LINEAR;
  sf_mlp_forward(&s, m->net.params, x, out);
}

static void net_forward_f(const sf_mlp_sky *m, const float *x, float *out, int depth) {
  sf_mlp_f net = m->net_f;
  if (depth) net.shape.output = SF_ACT_LINEAR;
  sf_mlp_forward_f(&net, x, out);
}

/* The horizon split's ground-ray network (scattering only, no depth mode). */
static void net_forward_ground_d(const sf_mlp_sky *m, const double *x, double *out) {
  sf_mlp_forward(&m->net_ground.shape, m->net_ground.params, x, out);
}
static void net_forward_ground_f(const sf_mlp_sky *m, const float *x, float *out) {
  sf_mlp_forward_f(&m->net_ground_f, x, out);
}

/* Where a segment ends (segment_end in models/mlp_sky_impl.inc). */
enum { SF_SEGMENT_END_INSIDE, SF_SEGMENT_END_GROUND, SF_SEGMENT_END_TOP };

#define REAL double
#define SKY_FN(name) name
#define R_SQRT sqrt
#define R_EXP exp
#define R_EXPM1 expm1
#define R_TANH tanh
#define NET_PARAMS(m) ((m)->net.params)
#define NET_FORWARD net_forward_d
#define NET_FORWARD_GROUND net_forward_ground_d
#define RAY_RADIUS_AT sf_ray_radius_at
#define RAY_ALTITUDE_AT sf_ray_altitude_at
#define RAY_DISC sf_ray_sphere_discriminant
#define RAY_INTERSECT sf_ray_sphere_intersections
#define SPHERE_FROM_ALTITUDES 0
#define OFFSET offset
#define SCALE scale
#define NORM_COEF coef
#define NORM_SLOPE edge_slope
#define NORM_CAP cap
#include "models/mlp_sky_impl.inc"
#undef REAL
#undef SKY_FN
#undef R_SQRT
#undef R_EXP
#undef R_EXPM1
#undef R_TANH
#undef NET_PARAMS
#undef NET_FORWARD
#undef NET_FORWARD_GROUND
#undef RAY_RADIUS_AT
#undef RAY_ALTITUDE_AT
#undef RAY_DISC
#undef RAY_INTERSECT
#undef SPHERE_FROM_ALTITUDES
#undef OFFSET
#undef SCALE
#undef NORM_COEF
#undef NORM_SLOPE
#undef NORM_CAP

#define REAL float
#define SKY_FN(name) name##_f
#define R_SQRT sqrtf
#define R_EXP expf
#define R_EXPM1 sf_emitted_expm1_f   /* the emitted skyfit_expm1 */
#define R_TANH tanhf
#define NET_PARAMS(m) ((m)->net_f.params)
#define NET_FORWARD net_forward_f
#define NET_FORWARD_GROUND net_forward_ground_f
#define RAY_RADIUS_AT sf_ray_radius_at_f
#define RAY_ALTITUDE_AT sf_ray_altitude_at_f
#define RAY_DISC sf_ray_sphere_discriminant_f
#define SPHERE_FROM_ALTITUDES 1   /* as the emitted code */
#define OFFSET offset_f
#define SCALE scale_f
#define NORM_COEF coef_f
#define NORM_SLOPE edge_slope_f
#define NORM_CAP cap_f
#include "models/mlp_sky_impl.inc"

static const char *const input_map_names[] = {"sqrt_h_mu", "bruneton"};
static const char *const input_names[2][2] = {{"sqrt_h_km", "mu"}, {"x_r", "x_mu"}};

const char *sf_mlp_input_map_name(sf_mlp_input_map m) { return (unsigned)m < 2u ? input_map_names[m] : "?"; }

int sf_mlp_input_map_parse(const char *name, sf_mlp_input_map *out) {
  for (int k = 0; k < 2; ++k)
    if (strcmp(name, input_map_names[k]) == 0) {
      *out = (sf_mlp_input_map)k;
      return 0;
    }
  return -1;
}

const char *sf_mlp_input_map_input_name(sf_mlp_input_map m, int k) {
  return (unsigned)m < 2u && (unsigned)k < 2u ? input_names[m][k] : "?";
}

void sf_mlp_bruneton_coords(double bottom_radius_km, double top_radius_km, double h_km, double mu, double *x_r,
                            double *x_mu) {
  double R = bottom_radius_km, Rt = top_radius_km;
  bruneton_coords(R, Rt, Rt - R, sqrt((Rt - R) * (Rt + R)), h_km, mu, x_r, x_mu);
}

void sf_mlp_bruneton_inverse(double bottom_radius_km, double top_radius_km, double x_r, double x_mu, double *h_km,
                             double *mu) {
  double R = bottom_radius_km, Rt = top_radius_km;
  double H = sqrt((Rt - R) * (Rt + R));
  double rho = H * fmin(fmax(x_r, 0.0), 1.0);
  double r = sqrt(rho * rho + R * R);
  double d_min = Rt - r, d_max = rho + H;
  double d = d_min + fmin(fmax(x_mu, 0.0), 1.0) * (d_max - d_min);
  *h_km = fmax(r - R, 0.0);
  /* Rt^2 = r^2 + d^2 + 2 r d mu */
  *mu = d <= 0.0 ? 1.0 : fmin(fmax((H * H - rho * rho - d * d) / (2.0 * r * d), -1.0), 1.0);
}

int sf_mlp_sky_make(sf_mlp_sky *m, sf_mlp *net, sf_mlp_target target, const sf_atmosphere *atm,
                    const double *offset, const double *scale, int n_single, const int *phase_constituent,
                    sf_error *err) {
  memset(m, 0, sizeof *m);
  const sf_mlp_shape *s = &net->shape;
  int n_in = target == SF_MLP_TARGET_TRANSMITTANCE_TOP ? 2 : 4;
  int n_out_expected = target == SF_MLP_TARGET_SEPARATE ? (n_single + 1) * atm->n_channels : atm->n_channels;
  if (s->sizes[0] != n_in || s->sizes[s->n_layers] != n_out_expected) {
    sf_fail(err, SF_ERR_INPUT, "network %d -> %d does not fit target %s (%d -> %d for %d channels)", s->sizes[0],
            s->sizes[s->n_layers], sf_mlp_target_name(target), n_in, n_out_expected, atm->n_channels);
    sf_mlp_free(net);
    return SF_ERR_INPUT;
  }
  m->net = *net;
  memset(net, 0, sizeof *net);
  if (sf_mlp_to_float(&m->net, &m->net_f)) {
    sf_mlp_sky_free(m);
    return sf_fail(err, SF_ERR_INTERNAL, "out of memory");
  }
  m->target = target;
  m->n_inputs = n_in;
  for (int k = 0; k < n_in; ++k) {
    m->offset[k] = offset[k];
    m->scale[k] = scale[k];
    m->offset_f[k] = (float)offset[k];
    m->scale_f[k] = (float)scale[k];
  }
  m->bottom_radius_km = atm->bottom_radius_km;
  m->top_radius_km = atm->top_radius_km;
  m->n_channels = atm->n_channels;
  m->n_single = target == SF_MLP_TARGET_SEPARATE ? n_single : 0;
  for (int k = 0; k < m->n_single; ++k) m->phases[k] = atm->constituents[phase_constituent[k]].phase;
  return SF_OK;
}

void sf_mlp_sky_free(sf_mlp_sky *m) {
  sf_mlp_free(&m->net);
  sf_mlp_f_free(&m->net_f);
  sf_mlp_free(&m->net_ground);
  sf_mlp_f_free(&m->net_ground_f);
  m->horizon_split = 0;
}

int sf_mlp_sky_set_ground_net(sf_mlp_sky *m, sf_mlp *net, sf_error *err) {
  const sf_mlp_shape *a = &m->net.shape, *b = &net->shape;
  int same = m->target != SF_MLP_TARGET_TRANSMITTANCE_TOP && a->n_layers == b->n_layers && a->hidden == b->hidden &&
             a->output == b->output;
  for (int l = 0; same && l <= a->n_layers; ++l) same = a->sizes[l] == b->sizes[l];
  if (!same) {
    sf_mlp_free(net);
    return sf_fail(err, SF_ERR_INPUT, "the ground-ray network must be a scattering network's second copy: "
                   "the same layers and activations");
  }
  sf_mlp_free(&m->net_ground);
  sf_mlp_f_free(&m->net_ground_f);
  m->net_ground = *net;
  memset(net, 0, sizeof *net);
  if (sf_mlp_to_float(&m->net_ground, &m->net_ground_f)) {
    sf_mlp_free(&m->net_ground);
    return sf_fail(err, SF_ERR_INTERNAL, "out of memory");
  }
  m->horizon_split = 1;
  return SF_OK;
}

void sf_mlp_output_norm_finish(sf_mlp_output_norm *n) {
  int A = n->degree_h, C = n->degree_mu_s, n_coef = (A + 1) * (C + 1);
  for (int k = 0; k < SF_MLP_NORM_MAX_COEFS; ++k) {
    if (k >= n_coef) n->coef[k] = 0.0;
    n->coef_f[k] = (float)n->coef[k];
  }
  /* dP/dv at v = -1: sum_c c coef[a][c] (-1)^(c-1) */
  for (int a = 0; a <= SF_MLP_NORM_MAX_DEGREE; ++a) {
    double s = 0.0;
    for (int c = 1; a <= A && c <= C; ++c) s += (c % 2 ? 1.0 : -1.0) * c * n->coef[a * (C + 1) + c];
    n->edge_slope[a] = s;
    n->edge_slope_f[a] = (float)s;
  }
  n->cap_f = n->has_cap ? (float)n->cap : 0.0f;
  n->active = 1;
}

double sf_mlp_output_norm_log_brightness(const sf_mlp_output_norm *n, double u, double v) {
  return log_brightness(n, u, v);
}

/* |cap| within SF_MLP_NORM_CAP_LIMIT (and not NaN) */
static int norm_cap_valid(double cap) { return fabs(cap) < SF_MLP_NORM_CAP_LIMIT; }

int sf_mlp_sky_set_output_norm(sf_mlp_sky *m, int ground, const sf_mlp_output_norm *norm, sf_error *err) {
  const sf_mlp *net = ground ? &m->net_ground : &m->net;
  if (m->target == SF_MLP_TARGET_TRANSMITTANCE_TOP || !net->params)
    return sf_fail(err, SF_ERR_INPUT, "brightness normalisation: only for a scattering model's %s network",
                   ground ? "ground-ray" : "sky");
  if (norm->degree_h < 0 || norm->degree_h > SF_MLP_NORM_MAX_DEGREE || norm->degree_mu_s < 0 ||
      norm->degree_mu_s > SF_MLP_NORM_MAX_DEGREE)
    return sf_fail(err, SF_ERR_INPUT, "brightness normalisation: degrees %d, %d: expected 0..%d", norm->degree_h,
                   norm->degree_mu_s, SF_MLP_NORM_MAX_DEGREE);
  if (norm->has_cap && !norm_cap_valid(norm->cap))
    return sf_fail(err, SF_ERR_INPUT, "brightness normalisation: cap %g: expected a finite log brightness in (-%g, %g)",
                   norm->cap, SF_MLP_NORM_CAP_LIMIT, SF_MLP_NORM_CAP_LIMIT);
  sf_mlp_output_norm *dst = ground ? &m->norm_ground : &m->norm;
  *dst = *norm;
  sf_mlp_output_norm_finish(dst);
  return SF_OK;
}

/* params <prefix>norm_coef ((A+1) x (C+1)) and, with a cap, <prefix>norm_cap
 * (one value) of the weights file (SPEC §8). */
static int add_norm_params(cJSON *doc, const sf_mlp_output_norm *n, const char *prefix) {
  char name[64];
  int shape[2] = {n->degree_h + 1, n->degree_mu_s + 1};
  snprintf(name, sizeof name, "%snorm_coef", prefix);
  if (sf_weights_add_param(doc, name, 2, shape, n->coef)) return SF_ERR_INTERNAL;
  snprintf(name, sizeof name, "%snorm_cap", prefix);
  return n->has_cap && sf_weights_add_param(doc, name, 1, (const int[]){1}, &n->cap) ? SF_ERR_INTERNAL : SF_OK;
}

int sf_mlp_sky_add_norms_to_weights(cJSON *doc, const sf_mlp_sky *m) {
  if (m->norm.active && add_norm_params(doc, &m->norm, "")) return SF_ERR_INTERNAL;
  if (m->horizon_split && m->norm_ground.active && add_norm_params(doc, &m->norm_ground, "ground_"))
    return SF_ERR_INTERNAL;
  return SF_OK;
}

/* Reads a network's normalisation if the file has one (optional: a file
 * without it holds a network of raw targets). */
static int load_norm(const sf_weights *w, sf_mlp_sky *m, int ground, sf_error *err) {
  const char *prefix = ground ? "ground_" : "";
  char name[64];
  snprintf(name, sizeof name, "%snorm_coef", prefix);
  const cJSON *params = cJSON_GetObjectItemCaseSensitive(w->root, "params");
  if (!cJSON_GetObjectItemCaseSensitive(params, name)) return SF_OK;
  sf_mlp_output_norm n;
  memset(&n, 0, sizeof n);
  int shape[2] = {-1, -1};
  if (sf_weights_param(w, name, 2, shape, n.coef, SF_MLP_NORM_MAX_COEFS, err)) return err->status;
  n.degree_h = shape[0] - 1;
  n.degree_mu_s = shape[1] - 1;
  char cap_name[64];
  snprintf(cap_name, sizeof cap_name, "%snorm_cap", prefix);
  if (cJSON_GetObjectItemCaseSensitive(params, cap_name)) {
    int cap_shape[1] = {1};
    if (sf_weights_param(w, cap_name, 1, cap_shape, &n.cap, 1, err)) return err->status;
    n.has_cap = 1;
    if (!norm_cap_valid(n.cap))
      return sf_fail(err, SF_ERR_INPUT, "%s: params.%s: %g: expected a finite log brightness in (-%g, %g)", w->source,
                     cap_name, n.cap, SF_MLP_NORM_CAP_LIMIT, SF_MLP_NORM_CAP_LIMIT);
  }
  if (sf_mlp_sky_set_output_norm(m, ground, &n, err)) {
    char message[1024];
    snprintf(message, sizeof message, "%.400s: params.%s: %.500s", w->source, name, err->message);
    snprintf(err->message, sizeof err->message, "%s", message);
    return err->status;
  }
  return SF_OK;
}

int sf_mlp_sky_from_weights(const sf_weights *w, sf_mlp_sky *m, sf_error *err) {
  memset(m, 0, sizeof *m);
  const cJSON *training = cJSON_GetObjectItemCaseSensitive(w->root, "training");
  const cJSON *target_item = cJSON_GetObjectItemCaseSensitive(training, "target");
  sf_mlp_target target;
  if (!cJSON_IsString(target_item) || sf_mlp_target_parse(target_item->valuestring, &target))
    return sf_fail(err, SF_ERR_INPUT, "%s: training.target: expected transmittance_top, radiance or separate",
                   w->source);
  /* The file's model names what its network gives. */
  int scattering_model = strcmp(w->model, "mlp-scattering") == 0;
  if ((scattering_model || strcmp(w->model, "mlp-transmittance") == 0) &&
      (target == SF_MLP_TARGET_TRANSMITTANCE_TOP) == scattering_model)
    return sf_fail(err, SF_ERR_INPUT, "%s: training.target: \"%s\" does not fit model \"%s\"", w->source,
                   sf_mlp_target_name(target), w->model);
  static const char *const names[4] = {"sqrt_h_km", "mu", "mu_s", "nu"};
  int n_in = target == SF_MLP_TARGET_TRANSMITTANCE_TOP ? 2 : 4;
  if (w->n_inputs != n_in)
    return sf_fail(err, SF_ERR_INPUT, "%s: inputs: expected %d entries, got %d", w->source, n_in, w->n_inputs);
  /* the input names say the mapping; "sqrt_h_km", "mu" is the original one */
  sf_mlp_input_map input_map = SF_MLP_INPUTS_SQRT_H_MU;
  if (target == SF_MLP_TARGET_TRANSMITTANCE_TOP && strcmp(w->inputs[0].name, input_names[1][0]) == 0)
    input_map = SF_MLP_INPUTS_BRUNETON;
  double offset[4], scale[4];
  for (int k = 0; k < n_in; ++k) {
    const char *expected = k < 2 ? input_names[input_map][k] : names[k];
    if (strcmp(w->inputs[k].name, expected) != 0)
      return sf_fail(err, SF_ERR_INPUT, "%s: inputs[%d].name: expected \"%s\", got \"%s\"", w->source, k,
                     expected, w->inputs[k].name);
    offset[k] = w->inputs[k].offset;
    scale[k] = w->inputs[k].scale;
  }
  int n_single = 0, constituent[SF_MAX_CONSTITUENTS];
  if (target == SF_MLP_TARGET_SEPARATE) {
    const cJSON *comps = cJSON_GetObjectItemCaseSensitive(training, "components");
    int n = cJSON_IsArray(comps) ? cJSON_GetArraySize(comps) : 0;
    if (n < 2 || n > SF_MAX_CONSTITUENTS + 1)
      return sf_fail(err, SF_ERR_INPUT, "%s: training.components: expected the scattering constituents' names "
                     "then \"multiple\"", w->source);
    for (int k = 0; k + 1 < n; ++k) {
      const cJSON *c = cJSON_GetArrayItem(comps, k);
      int idx = cJSON_IsString(c) ? sf_atmosphere_find(&w->atmosphere, c->valuestring) : -1;
      if (idx < 0)
        return sf_fail(err, SF_ERR_INPUT, "%s: training.components[%d]: not a constituent of the atmosphere",
                       w->source, k);
      constituent[n_single++] = idx;
    }
  }
  sf_mlp net;
  if (sf_mlp_from_weights(w, &net, err)) return err->status;
  if (sf_mlp_sky_make(m, &net, target, &w->atmosphere, offset, scale, n_single, constituent, err)) {
    char message[1024];
    snprintf(message, sizeof message, "%.400s: params: %.600s", w->source, err->message);
    snprintf(err->message, sizeof err->message, "%s", message);
    return err->status;
  }
  m->input_map = input_map;
  if (target != SF_MLP_TARGET_TRANSMITTANCE_TOP && sf_mlp_weights_has(w, "ground_")) {
    sf_mlp ground;
    if (sf_mlp_from_weights_prefixed(w, "ground_", &ground, err)) {
      sf_mlp_sky_free(m);
      return err->status;
    }
    if (sf_mlp_sky_set_ground_net(m, &ground, err)) {
      char message[1024];
      snprintf(message, sizeof message, "%.380s: params ground_W0 ...: %.600s", w->source, err->message);
      snprintf(err->message, sizeof err->message, "%s", message);
      sf_mlp_sky_free(m);
      return err->status;
    }
  }
  if ((target != SF_MLP_TARGET_TRANSMITTANCE_TOP &&
       (load_norm(w, m, 0, err) || (m->horizon_split && load_norm(w, m, 1, err)))) ||
      sf_weights_check_params_read(w, err)) {
    sf_mlp_sky_free(m);
    return err->status;
  }
  return SF_OK;
}

int sf_mlp_sky_load(const char *path, sf_mlp_sky *m, sf_error *err) {
  memset(m, 0, sizeof *m);
  sf_weights w;
  if (sf_weights_load_file(path, NULL, &w, err)) return err->status;
  int status = SF_OK;
  if (strcmp(w.model, "mlp-transmittance") != 0 && strcmp(w.model, "mlp-scattering") != 0)
    status = sf_fail(err, SF_ERR_INPUT, "%s: model: expected \"mlp-transmittance\" or \"mlp-scattering\", got \"%s\"",
                     path, w.model);
  else
    status = sf_mlp_sky_from_weights(&w, m, err);
  sf_weights_free(&w);
  return status;
}
