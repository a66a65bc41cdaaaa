/* Pieces of the neural sky's emitted code shared by codegen/emit_mlp.c (the
 * networks' forward passes) and codegen/emit_mlp_depth_diff.c (the depth
 * difference of eq. 43): how a network's layers are split into GLSL pieces
 * of at most 4 units, named and declared as constants. Internal to
 * codegen/. */
#ifndef SKYFIT_CODEGEN_EMIT_MLP_PARTS_H
#define SKYFIT_CODEGEN_EMIT_MLP_PARTS_H

#include <stddef.h>

#include "codegen/code_writer.h"
#include "models/mlp.h"

#define SF_MLP_CODE_MAX_CHUNKS ((SF_MLP_MAX_WIDTH + 1) / 2)

/* A network's outputs in GLSL: the last layer's pieces (sizes) named
 * prefix{last}_{c}. */
typedef struct sf_mlp_code_outputs {
  int n_chunks, sizes[SF_MLP_CODE_MAX_CHUNKS];
  int last;     /* layer index of the output pieces (GLSL names) */
} sf_mlp_code_outputs;

/* Member k of a value of n floats: ".x" ... ".w" ("" for a plain float). */
const char *sf_mlp_code_member(int n, int k);
/* Splits n units into pieces of at most 4: `by` units each when by > 0
 * (the separate target's per-channel blocks), else as evenly as possible
 * (8 -> 4 4, 9 -> 3 3 3, 5 -> 3 2). Returns the number of pieces. */
int sf_mlp_code_chunk_sizes(int n, int by, int *sizes);
/* The GLSL float type of n values: "float", "vec2" ... "vec4". */
void sf_mlp_code_glsl_type(int n, char *out, size_t size);
/* GLSL: output k among the pieces of o, named prefix{last}_{c}{member}. */
void sf_mlp_code_piece_name(const sf_mlp_code_outputs *o, const char *prefix, int k, char *out, size_t n);
/* C: the network's parameters as one flat `static const float p[]`,
 * models/mlp.h order: W0 row-major, b0, W1, b1, ... */
void sf_mlp_code_params_c(sf_code_writer *w, const sf_mlp_f *net);
/* GLSL: the constants of layer l's output piece oc (R rows from row0 of
 * the layer's W and b, n_in inputs in n_in_chunks pieces): its biases
 * b{l}_{oc} and, per input piece, the weight block W{l}_{oc}_{ic} (a
 * matrix, or a vector where either side is one unit; column-major). */
void sf_mlp_code_piece_constants_glsl(sf_code_writer *w, int l, int oc, int R, int row0, const float *W,
                                      const float *b, int n_in, const int *in_sizes, int n_in_chunks);

/* GLSL: the sum of layer l's output piece oc (R rows) into sum: "b{l}_{oc}"
 * when with_bias, then per input piece "dot(W{l}_{oc}_{ic}, {input}{l}_{ic})"
 * (one output row, several inputs) or "W{l}_{oc}_{ic} * {input}{l}_{ic}",
 * joined by " + ". */
void sf_mlp_code_piece_sum_glsl(char *sum, size_t size, int l, int oc, int R, const int *in_sizes, int n_in_chunks,
                                const char *input, int with_bias);
/* o = the last layer's pieces: sizes[0 .. n_chunks - 1], layer `last`. */
void sf_mlp_code_outputs_set(sf_mlp_code_outputs *o, const int *sizes, int n_chunks, int last);

#endif
