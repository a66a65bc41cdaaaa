#include "models/mlp.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char *const activation_names[] = {"sigmoid", "tanh", "relu", "linear", "exp_neg", "exp_neg_exp"};

const char *sf_mlp_activation_name(sf_mlp_activation a) {
  return (unsigned)a < (unsigned)SF_MLP_ACTIVATION_COUNT ? activation_names[a] : "?";
}

int sf_mlp_activation_parse(const char *name, sf_mlp_activation *out) {
  for (int k = 0; k < SF_MLP_ACTIVATION_COUNT; ++k)
    if (strcmp(name, activation_names[k]) == 0) {
      *out = (sf_mlp_activation)k;
      return 0;
    }
  return -1;
}

int sf_mlp_activation_can_be_negative(sf_mlp_activation a) { return a == SF_ACT_LINEAR || a == SF_ACT_TANH; }

int sf_mlp_shape_parse_layers(const char *text, sf_mlp_shape *shape, sf_error *err) {
  int sizes[SF_MLP_MAX_LAYERS + 2];
  int n = 0;
  const char *p = text;
  while (1) {
    char *end;
    errno = 0;
    long v = strtol(p, &end, 10);
    if (end == p || errno == ERANGE || v < 1 || v > SF_MLP_MAX_WIDTH || n >= SF_MLP_MAX_LAYERS + 1)
      return sf_fail(err, SF_ERR_INPUT,
                     "--layers: expected 2 to %d comma-separated layer sizes in 1..%d, got '%s'",
                     SF_MLP_MAX_LAYERS + 1, SF_MLP_MAX_WIDTH, text);
    sizes[n++] = (int)v;
    if (*end == '\0') break;
    if (*end != ',')
      return sf_fail(err, SF_ERR_INPUT, "--layers: expected sizes separated by commas, got '%s'", text);
    p = end + 1;
  }
  if (n < 2)
    return sf_fail(err, SF_ERR_INPUT, "--layers: need at least an input and an output size, got '%s'", text);
  shape->n_layers = n - 1;
  for (int k = 0; k < n; ++k) shape->sizes[k] = sizes[k];
  return SF_OK;
}

int sf_mlp_param_count(const sf_mlp_shape *s) {
  int n = 0;
  for (int l = 0; l < s->n_layers; ++l) n += s->sizes[l + 1] * (s->sizes[l] + 1);
  return n;
}

int sf_mlp_weight_offset(const sf_mlp_shape *s, int layer) {
  int n = 0;
  for (int l = 0; l < layer; ++l) n += s->sizes[l + 1] * (s->sizes[l] + 1);
  return n;
}

int sf_mlp_bias_offset(const sf_mlp_shape *s, int layer) {
  return sf_mlp_weight_offset(s, layer) + s->sizes[layer + 1] * s->sizes[layer];
}

int sf_mlp_init(sf_mlp *net, const sf_mlp_shape *shape) {
  net->shape = *shape;
  net->n_params = sf_mlp_param_count(shape);
  net->params = calloc((size_t)net->n_params, sizeof(double));
  return net->params ? 0 : -1;
}

void sf_mlp_free(sf_mlp *net) {
  free(net->params);
  net->params = NULL;
  net->n_params = 0;
}

double sf_mlp_activate(sf_mlp_activation a, double z) {
  switch (a) {
    case SF_ACT_SIGMOID: return 1.0 / (1.0 + exp(-z));
    case SF_ACT_TANH: return tanh(z);
    case SF_ACT_RELU: return z > 0.0 ? z : 0.0;
    case SF_ACT_LINEAR: return z;
    case SF_ACT_EXP_NEG: return exp(-z);
    case SF_ACT_EXP_NEG_EXP: return exp(-exp(-z));
  }
  return z;
}

/* exp(-z) of float overflows to +inf for z < -88.7 and 1/(1+inf) is 0, never
 * NaN: both forms are finite or saturate cleanly (SPEC §10). exp_neg is
 * clamped so that a wild input cannot produce inf. */
float sf_mlp_activate_f(sf_mlp_activation a, float z) {
  switch (a) {
    case SF_ACT_SIGMOID: return 1.0f / (1.0f + expf(-z));
    case SF_ACT_TANH: return tanhf(z);
    case SF_ACT_RELU: return z > 0.0f ? z : 0.0f;
    case SF_ACT_LINEAR: return z;
    case SF_ACT_EXP_NEG: return expf(-fmaxf(z, -80.0f));
    case SF_ACT_EXP_NEG_EXP: return expf(-expf(-fmaxf(z, -80.0f)));
  }
  return z;
}

void sf_mlp_forward(const sf_mlp_shape *s, const double *params, const double *x, double *out) {
  double buf[2][SF_MLP_MAX_WIDTH];
  const double *a = x;
  const double *p = params;
  for (int l = 0; l < s->n_layers; ++l) {
    int n_in = s->sizes[l], n_out = s->sizes[l + 1];
    const double *W = p, *b = p + n_out * n_in;
    sf_mlp_activation f = l + 1 == s->n_layers ? s->output : s->hidden;
    double *z = l + 1 == s->n_layers ? out : buf[l & 1];
    for (int i = 0; i < n_out; ++i) {
      double sum = b[i];
      for (int j = 0; j < n_in; ++j) sum += W[i * n_in + j] * a[j];
      z[i] = sf_mlp_activate(f, sum);
    }
    a = z;
    p += n_out * (n_in + 1);
  }
}

int sf_mlp_to_float(const sf_mlp *net, sf_mlp_f *out) {
  out->shape = net->shape;
  out->n_params = net->n_params;
  out->params = malloc((size_t)net->n_params * sizeof(float));
  if (!out->params) return -1;
  for (int k = 0; k < net->n_params; ++k) out->params[k] = (float)net->params[k];
  return 0;
}

void sf_mlp_f_free(sf_mlp_f *net) {
  free(net->params);
  net->params = NULL;
}

void sf_mlp_forward_f(const sf_mlp_f *net, const float *x, float *out) {
  const sf_mlp_shape *s = &net->shape;
  float buf[2][SF_MLP_MAX_WIDTH];
  const float *a = x;
  const float *p = net->params;
  for (int l = 0; l < s->n_layers; ++l) {
    int n_in = s->sizes[l], n_out = s->sizes[l + 1];
    const float *W = p, *b = p + n_out * n_in;
    sf_mlp_activation f = l + 1 == s->n_layers ? s->output : s->hidden;
    float *z = l + 1 == s->n_layers ? out : buf[l & 1];
    for (int i = 0; i < n_out; ++i) {
      float sum = b[i];
      for (int j = 0; j < n_in; ++j) sum += W[i * n_in + j] * a[j];
      z[i] = sf_mlp_activate_f(f, sum);
    }
    a = z;
    p += n_out * (n_in + 1);
  }
}

int sf_mlp_add_params_to_weights(cJSON *doc, const sf_mlp *net, const char *prefix) {
  const sf_mlp_shape *s = &net->shape;
  for (int l = 0; l < s->n_layers; ++l) {
    char name[48];
    int wshape[2] = {s->sizes[l + 1], s->sizes[l]};
    snprintf(name, sizeof name, "%sW%d", prefix, l);
    if (sf_weights_add_param(doc, name, 2, wshape, net->params + sf_mlp_weight_offset(s, l))) return -1;
    snprintf(name, sizeof name, "%sb%d", prefix, l);
    if (sf_weights_add_param(doc, name, 1, wshape, net->params + sf_mlp_bias_offset(s, l))) return -1;
  }
  return 0;
}

int sf_mlp_add_to_weights(cJSON *doc, const sf_mlp *net) {
  const sf_mlp_shape *s = &net->shape;
  cJSON *training = sf_weights_training(doc);
  if (!training) return -1;
  cJSON_AddStringToObject(training, "hidden_activation", sf_mlp_activation_name(s->hidden));
  cJSON_AddStringToObject(training, "output_activation", sf_mlp_activation_name(s->output));
  cJSON *layers = cJSON_AddArrayToObject(training, "layers");
  if (!layers) return -1;
  for (int l = 0; l <= s->n_layers; ++l) cJSON_AddItemToArray(layers, cJSON_CreateNumber(s->sizes[l]));
  return sf_mlp_add_params_to_weights(doc, net, "");
}

static int read_activation(const sf_weights *w, const cJSON *training, const char *key,
                           sf_mlp_activation *out, sf_error *err) {
  const cJSON *v = training ? cJSON_GetObjectItemCaseSensitive(training, key) : NULL;
  if (!cJSON_IsString(v) || sf_mlp_activation_parse(v->valuestring, out))
    return sf_fail(err, SF_ERR_INPUT,
                   "%s: training.%s: expected one of sigmoid, tanh, relu, linear, exp_neg, exp_neg_exp", w->source, key);
  return SF_OK;
}

int sf_mlp_weights_has(const sf_weights *w, const char *prefix) {
  char name[48];
  snprintf(name, sizeof name, "%sW0", prefix);
  return cJSON_GetObjectItemCaseSensitive(cJSON_GetObjectItemCaseSensitive(w->root, "params"), name) != NULL;
}

int sf_mlp_from_weights(const sf_weights *w, sf_mlp *net, sf_error *err) {
  return sf_mlp_from_weights_prefixed(w, "", net, err);
}

int sf_mlp_from_weights_prefixed(const sf_weights *w, const char *prefix, sf_mlp *net, sf_error *err) {
  memset(net, 0, sizeof *net);
  const cJSON *training = cJSON_GetObjectItemCaseSensitive(w->root, "training");
  sf_mlp_shape s;
  memset(&s, 0, sizeof s);
  if (read_activation(w, training, "hidden_activation", &s.hidden, err) ||
      read_activation(w, training, "output_activation", &s.output, err))
    return SF_ERR_INPUT;
  /* Layer count: W0, W1, ... until one is missing; the shapes chain. */
  const cJSON *params = cJSON_GetObjectItemCaseSensitive(w->root, "params");
  int n_layers = 0;
  for (; n_layers <= SF_MLP_MAX_LAYERS; ++n_layers) {
    char name[48];
    snprintf(name, sizeof name, "%sW%d", prefix, n_layers);
    if (!cJSON_GetObjectItemCaseSensitive(params, name)) break;
  }
  if (n_layers < 1 || n_layers > SF_MLP_MAX_LAYERS)
    return sf_fail(err, SF_ERR_INPUT, "%s: params: expected %sW0 .. %sW%d (1 to %d layers), found %d", w->source,
                   prefix, prefix, SF_MLP_MAX_LAYERS - 1, SF_MLP_MAX_LAYERS, n_layers);
  s.n_layers = n_layers;
  double *scratch = malloc(sizeof(double) * SF_MLP_MAX_WIDTH * SF_MLP_MAX_WIDTH);
  if (!scratch) return sf_fail(err, SF_ERR_INTERNAL, "out of memory");
  for (int l = 0; l < n_layers; ++l) {
    char name[48];
    int shape[2] = {-1, l == 0 ? -1 : s.sizes[l]};
    snprintf(name, sizeof name, "%sW%d", prefix, l);
    if (sf_weights_param(w, name, 2, shape, scratch, SF_MLP_MAX_WIDTH * SF_MLP_MAX_WIDTH, err)) {
      free(scratch);
      return SF_ERR_INPUT;
    }
    /* The evaluators' buffers hold SF_MLP_MAX_WIDTH units a layer (a file
     * of 2000 had overrun the stack). */
    for (int axis = l == 0 ? 1 : 0; axis >= 0; --axis)
      if (shape[axis] < 1 || shape[axis] > SF_MLP_MAX_WIDTH) {
        free(scratch);
        return sf_fail(err, SF_ERR_INPUT, "%s: params.%s: %d %s, expected 1 to %d", w->source, name, shape[axis],
                       axis ? "columns (inputs)" : "rows (units)", SF_MLP_MAX_WIDTH);
      }
    if (l == 0) s.sizes[0] = shape[1];
    s.sizes[l + 1] = shape[0];
  }
  free(scratch);
  if (w->n_inputs != s.sizes[0])
    return sf_fail(err, SF_ERR_INPUT, "%s: inputs: %d entries, but %sW0 has %d columns", w->source, w->n_inputs,
                   prefix, s.sizes[0]);
  if (sf_mlp_init(net, &s)) return sf_fail(err, SF_ERR_INTERNAL, "out of memory");
  for (int l = 0; l < n_layers; ++l) {
    char name[48];
    int wshape[2] = {s.sizes[l + 1], s.sizes[l]};
    int bshape[1] = {s.sizes[l + 1]};
    snprintf(name, sizeof name, "%sW%d", prefix, l);
    if (sf_weights_param(w, name, 2, wshape, net->params + sf_mlp_weight_offset(&s, l), wshape[0] * wshape[1],
                         err))
      goto fail;
    snprintf(name, sizeof name, "%sb%d", prefix, l);
    if (sf_weights_param(w, name, 1, bshape, net->params + sf_mlp_bias_offset(&s, l), bshape[0], err))
      goto fail;
  }
  return SF_OK;
fail:
  sf_mlp_free(net);
  return SF_ERR_INPUT;
}
