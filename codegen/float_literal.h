/* Float constants for emitted code (SPEC §9): the shortest decimal text
 * that reads back as exactly the same float32, written so that C99, C++ and
 * GLSL >= 1.30 all parse it as a float (a '.' or an exponent, then 'f'):
 * "0.125f", "-1.0f", "3.40282347e+38f", "1e-45f". Reading it back with
 * strtof (C) or as a GLSL literal gives the identical bits; a GPU that
 * flushes denormals reads a denormal as 0. */
#ifndef SKYFIT_CODEGEN_FLOAT_LITERAL_H
#define SKYFIT_CODEGEN_FLOAT_LITERAL_H

#define SF_FLOAT_LITERAL_LEN 32

/* Writes the literal for v into out. Returns 0, or -1 (out = "") when v is
 * NaN or infinite: such constants have no literal and must not be emitted. */
int sf_float_literal(float v, char out[SF_FLOAT_LITERAL_LEN]);

#endif
