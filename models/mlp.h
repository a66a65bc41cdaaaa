/* Multilayer perceptrons of the neural sky (SPEC §7.4-7.5, seed 000 §9.6):
 * the network, its forward pass in double (training, reference) and float32
 * (what emitted shaders do), and its weights file.
 *
 * Network. n_layers weight layers map n[0] inputs to n[n_layers] outputs:
 *   a_0 = normalised inputs,
 *   z_l = W_l a_l + b_l,          W_l has n[l+1] rows and n[l] columns,
 *   a_{l+1} = f_l(z_l),           f_l = hidden activation for l < n_layers-1,
 *                                 output activation for the last layer.
 * Activations: sigmoid 1/(1+e^-z), tanh, relu max(z,0), linear z, and (output
 * only, seed 000 §9.6.2) exp_neg = e^-z (a positive output spanning orders
 * of magnitude: the last layer predicts -log of the quantity), and (output
 * only) exp_neg_exp = exp(-exp(-z)), the double exponential Leenman observed
 * in the transmittance (seed 000 eq. 41): the optical depth is e^-z, so the
 * last layer predicts -log(optical depth), which is nearly linear in h.
 *
 * Flat parameter order (training, checkpoints): for l = 0.., W_l row-major
 * (row = output unit, column = input unit) then b_l.
 *
 * Weights file (models/weights_file.h, SPEC §8):
 *   "model": "mlp-transmittance" | "mlp-scattering" (| "mlp" for CSV fits),
 *   "quantity": "transmittance" | "sky_radiance" | "values",
 *   "inputs": one entry per network input, in order, with
 *       normalised = (value - offset) * scale,
 *     where value is the physical input named by "name":
 *       "sqrt_h_km"  sqrt(h), h = viewer altitude above the bottom radius in km
 *                    (Leenman's table coordinate, seed 000 §9.1: more samples
 *                    near the ground), the viewer first moved to the top
 *                    boundary if it is above it;
 *       "mu", "mu_s", "nu" the cosines of SPEC §3 (nu clamped as SPEC §3);
 *       "x_r", "x_mu" Bruneton's horizon-aware coordinates of (h, mu)
 *                    (transmittance network only, models/mlp_sky.h); the
 *                    names select the mapping, so files written before it
 *                    existed ("sqrt_h_km", "mu") load unchanged;
 *       "x0", "x1", ... for networks fitted to a CSV (already normalised:
 *                    offset 0, scale 1).
 *   "params": "W0" [n1][n0], "b0" [n1], "W1" [n2][n1], "b1" [n2], ...
 *     (W_l[row = output][column = input]; in GLSL, whose matrices are
 *     column-major, W_l is the matNxM with N = n[l] columns and M = n[l+1]
 *     rows, built from the transposed array, and z = W * a: a 2-4-3 network is
 *     mat2x4 W0, vec4 b0, mat4x3 W1, vec3 b1, as seed 000 §9.6.3; layers of 8
 *     are split into vec4 halves and 4x4 blocks).
 *   "training": {"hidden_activation": "sigmoid", "output_activation":
 *     "exp_neg", "target": ..., "layers": [n0, n1, ...], "loss", "seed",
 *     "epochs", ...}. "target" says what the outputs are, see
 *     models/mlp_sky.h.
 *
 * Evaluation of the sky quantities from the networks (eq. 43-44, reversed
 * rays, viewers in space) is in models/mlp_sky.h. */
#ifndef SKYFIT_MODELS_MLP_H
#define SKYFIT_MODELS_MLP_H

#include "models/weights_file.h"
#include "util/error.h"

#define SF_MLP_MAX_LAYERS 8      /* weight layers */
#define SF_MLP_MAX_WIDTH 256     /* units per layer */

typedef enum sf_mlp_activation {
  SF_ACT_SIGMOID = 0,
  SF_ACT_TANH,
  SF_ACT_RELU,
  SF_ACT_LINEAR,
  SF_ACT_EXP_NEG,
  SF_ACT_EXP_NEG_EXP
} sf_mlp_activation;
#define SF_MLP_ACTIVATION_COUNT 6

/* Architecture: sizes[0..n_layers] and the two activations. */
typedef struct sf_mlp_shape {
  int n_layers;
  int sizes[SF_MLP_MAX_LAYERS + 1];
  sf_mlp_activation hidden, output;
} sf_mlp_shape;

/* A network: its shape and n_params doubles (order above), owned. */
typedef struct sf_mlp {
  sf_mlp_shape shape;
  int n_params;
  double *params;
} sf_mlp;

/* "sigmoid", "tanh", "relu", "linear", "exp_neg", "exp_neg_exp". */
const char *sf_mlp_activation_name(sf_mlp_activation a);
/* Returns 0 and sets *out, or -1 for an unknown name. */
int sf_mlp_activation_parse(const char *name, sf_mlp_activation *out);
/* 1 for linear and tanh, whose values can be negative (sigmoid, relu and
 * the exponentials cannot). */
int sf_mlp_activation_can_be_negative(sf_mlp_activation a);
/* "4,8,8,3" -> shape sizes (activations untouched). SF_ERR_INPUT naming the
 * text when it is not 2..SF_MLP_MAX_LAYERS+1 sizes in 1..SF_MLP_MAX_WIDTH. */
int sf_mlp_shape_parse_layers(const char *text, sf_mlp_shape *shape, sf_error *err);

int sf_mlp_param_count(const sf_mlp_shape *shape);
/* Offsets of W_l and b_l in the flat parameter array. */
int sf_mlp_weight_offset(const sf_mlp_shape *shape, int layer);
int sf_mlp_bias_offset(const sf_mlp_shape *shape, int layer);

/* Allocates a zero network of this shape; -1 when out of memory. */
int sf_mlp_init(sf_mlp *net, const sf_mlp_shape *shape);
void sf_mlp_free(sf_mlp *net);

/* f(z) and f'(z) expressed through a = f(z) where that is cheaper. */
double sf_mlp_activate(sf_mlp_activation a, double z);
float sf_mlp_activate_f(sf_mlp_activation a, float z);

/* Forward pass in double: out[n_out] from normalised inputs x[n_in]. */
void sf_mlp_forward(const sf_mlp_shape *shape, const double *params, const double *x, double *out);

/* The float32 network (what is exported and what shaders evaluate): the
 * parameters rounded to float once, every operation in float. */
typedef struct sf_mlp_f {
  sf_mlp_shape shape;
  int n_params;
  float *params;
} sf_mlp_f;
int sf_mlp_to_float(const sf_mlp *net, sf_mlp_f *out);
void sf_mlp_f_free(sf_mlp_f *net);
void sf_mlp_forward_f(const sf_mlp_f *net, const float *x, float *out);

/* Adds training.hidden_activation/output_activation/layers and params
 * W0, b0, ... to a weights document. Returns nonzero when out of memory. */
int sf_mlp_add_to_weights(cJSON *doc, const sf_mlp *net);
/* Adds a second network of the same activations as params <prefix>W0,
 * <prefix>b0, ... (e.g. "ground_", models/mlp_sky.h); its layer sizes are
 * read back from the arrays. */
int sf_mlp_add_params_to_weights(cJSON *doc, const sf_mlp *net, const char *prefix);
/* Reads the network back from a loaded weights file, checking the layer
 * shapes against each other and the inputs; SF_ERR_INPUT naming the file and
 * key otherwise. */
int sf_mlp_from_weights(const sf_weights *w, sf_mlp *net, sf_error *err);
/* The same for the params named <prefix>W0, <prefix>b0, ... */
int sf_mlp_from_weights_prefixed(const sf_weights *w, const char *prefix, sf_mlp *net, sf_error *err);
/* Whether the file holds params <prefix>W0. */
int sf_mlp_weights_has(const sf_weights *w, const char *prefix);

#endif
