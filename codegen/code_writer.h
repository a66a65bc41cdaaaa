/* A text buffer that writes one function body as C99/C++ or GLSL (SPEC §9).
 * Emitters write a neutral dialect once and the writer spells it for the
 * target language, so both languages get the same names, signatures and
 * arithmetic:
 *
 *   %s %d %%  as printf (%s inserted as it is);
 *   %E        a string argument that is itself in this dialect (an
 *             expression with @words), spelled for the target language;
 *   %F        a double argument rounded to float32 and printed as a literal
 *             that round-trips exactly (codegen/float_literal.h);
 *   @exp @log @sqrt @abs @min @max @pow
 *             the float32 math function (C: expf ... fminf; GLSL: exp ... min);
 *   %V %C     an int argument n: the type of n floats (n = 1: float, else
 *             @vecn) and its constructor with the opening parenthesis (n = 1:
 *             just "(");
 *   @vec2 @vec3 @vec4
 *             the vector type (C: skyfit_vec3, a struct with x, y, z, w;
 *             GLSL: vec3); directly followed by '(' the constructor
 *             (C: skyfit_make_vec3(...); GLSL: vec3(...));
 *   @fn       the qualifier of an emitted function (C: "static inline ",
 *             GLSL: nothing), so headers can be included by many files.
 *
 * Everything else (float arithmetic, if/else, for loops over int, .x .y .z
 * member access, ternaries) is spelled alike in both languages. Float
 * literals always carry 'f' so C never promotes to double.
 *
 * Errors (out of memory, an unknown @word, a non-finite constant) are
 * sticky: the first one is kept in problem and every later call does
 * nothing. */
#ifndef SKYFIT_CODEGEN_CODE_WRITER_H
#define SKYFIT_CODEGEN_CODE_WRITER_H

#include <stdarg.h>
#include <stddef.h>

typedef enum sf_code_lang { SF_CODE_C = 0, SF_CODE_GLSL = 1 } sf_code_lang;

/* Shared helper functions a body calls (codegen/emit_helpers.h). */
enum sf_code_helper {
  SF_HELPER_SPHERE_HITS = 1u << 0,   /* skyfit_sphere_hits */
  SF_HELPER_AIR_CLIP = 1u << 1,      /* skyfit_air_clip */
  SF_HELPER_ALTITUDE_AT = 1u << 2,   /* skyfit_altitude_at */
  SF_HELPER_SHELL_CHORD = 1u << 3,   /* skyfit_shell_chord */
  SF_HELPER_EXPM1 = 1u << 4,         /* skyfit_expm1 */
  SF_HELPER_CHAPMAN_UP = 1u << 5,    /* skyfit_chapman_diff */
  SF_HELPER_TAYLOR_PIECE = 1u << 6,  /* skyfit_taylor_piece */
  /* 1u << 7 was skyfit_sigmoid, used by no emitter now */
  SF_HELPER_ASIN_ACOS = 1u << 8,     /* skyfit_asin, skyfit_acos */
  SF_HELPER_RAY_ENTER = 1u << 9,     /* skyfit_ray_enter: space viewers to the top */
  SF_HELPER_RADIUS_AT = 1u << 10,    /* skyfit_radius_at */
  SF_HELPER_CLAMP_NU = 1u << 11      /* skyfit_clamp_nu (SPEC §3) */
};

typedef struct sf_code_writer {
  sf_code_lang lang;
  char *text;             /* NUL-terminated; NULL until something is written */
  size_t length, capacity;
  unsigned vec_sizes;     /* bit n set: vecN appears in the text */
  unsigned helpers;       /* SF_HELPER_* the text calls */
  int failed;
  char problem[256];
} sf_code_writer;

void sf_cw_init(sf_code_writer *w, sf_code_lang lang);
void sf_cw_free(sf_code_writer *w);

/* Appends fmt in the dialect above. */
void sf_cw_emit(sf_code_writer *w, const char *fmt, ...);
void sf_cw_emitv(sf_code_writer *w, const char *fmt, va_list args);
/* Appends text as it is (comments, already spelled code). */
void sf_cw_raw(sf_code_writer *w, const char *text);
/* Records that the text calls these helpers. */
void sf_cw_need(sf_code_writer *w, unsigned helpers);
/* A constant float array: C "static const float name[n] = {...};",
 * GLSL "const float name[n] = float[n](...);", one line per 4 values,
 * each line starting with indent. */
void sf_cw_const_floats(sf_code_writer *w, const char *indent, const char *name,
                        const double *values, int n);

#endif
