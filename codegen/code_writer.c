#include "codegen/code_writer.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "codegen/float_literal.h"

void sf_cw_init(sf_code_writer *w, sf_code_lang lang) {
  memset(w, 0, sizeof *w);
  w->lang = lang;
}

void sf_cw_free(sf_code_writer *w) {
  free(w->text);
  w->text = NULL;
  w->length = w->capacity = 0;
}

static void fail(sf_code_writer *w, const char *problem) {
  if (w->failed) return;
  w->failed = 1;
  snprintf(w->problem, sizeof w->problem, "%s", problem);
}

static void append(sf_code_writer *w, const char *s, size_t n) {
  if (w->failed) return;
  if (w->length + n + 1 > w->capacity) {
    size_t cap = w->capacity ? w->capacity : 4096;
    while (cap < w->length + n + 1) cap *= 2;
    char *grown = realloc(w->text, cap);
    if (!grown) {
      fail(w, "out of memory");
      return;
    }
    w->text = grown;
    w->capacity = cap;
  }
  memcpy(w->text + w->length, s, n);
  w->length += n;
  w->text[w->length] = '\0';
}

void sf_cw_raw(sf_code_writer *w, const char *text) { append(w, text, strlen(text)); }

void sf_cw_need(sf_code_writer *w, unsigned helpers) { w->helpers |= helpers; }

typedef struct math_name {
  const char *word, *c, *glsl;
} math_name;

static const math_name math_names[] = {
    {"exp", "expf", "exp"},   {"log", "logf", "log"},   {"sqrt", "sqrtf", "sqrt"},
    {"abs", "fabsf", "abs"},  {"min", "fminf", "min"},  {"max", "fmaxf", "max"},
    {"pow", "powf", "pow"},
};

/* Spells the @word starting at *p (just after '@') and advances *p. */
static void spell_word(sf_code_writer *w, const char **p) {
  const char *s = *p;
  size_t n = 0;
  while ((s[n] >= 'a' && s[n] <= 'z') || (s[n] >= '0' && s[n] <= '9')) ++n;
  char word[16];
  if (n == 0 || n >= sizeof word) {
    fail(w, "code template: bad @word");
    return;
  }
  memcpy(word, s, n);
  word[n] = '\0';
  *p = s + n;
  int glsl = w->lang == SF_CODE_GLSL;
  for (size_t i = 0; i < sizeof math_names / sizeof math_names[0]; ++i)
    if (strcmp(word, math_names[i].word) == 0) {
      sf_cw_raw(w, glsl ? math_names[i].glsl : math_names[i].c);
      return;
    }
  if (strcmp(word, "fn") == 0) {
    if (!glsl) sf_cw_raw(w, "static inline ");
    if (**p == ' ') ++*p;
    return;
  }
  if (n == 4 && strncmp(word, "vec", 3) == 0 && word[3] >= '2' && word[3] <= '4') {
    w->vec_sizes |= 1u << (word[3] - '0');
    int constructor = **p == '(';
    if (glsl) sf_cw_raw(w, word);
    else {
      sf_cw_raw(w, constructor ? "skyfit_make_" : "skyfit_");
      sf_cw_raw(w, word);
    }
    return;
  }
  char message[64];
  snprintf(message, sizeof message, "code template: unknown @%s", word);
  fail(w, message);
}

static void append_float(sf_code_writer *w, double value) {
  char literal[SF_FLOAT_LITERAL_LEN];
  if (sf_float_literal((float)value, literal) != 0) {
    char message[96];
    snprintf(message, sizeof message, "constant %.17g is not a finite float32", value);
    fail(w, message);
    return;
  }
  sf_cw_raw(w, literal);
}

void sf_cw_emitv(sf_code_writer *w, const char *fmt, va_list args) {
  const char *p = fmt;
  while (*p && !w->failed) {
    const char *run = p;
    while (*p && *p != '%' && *p != '@') ++p;
    append(w, run, (size_t)(p - run));
    if (*p == '@') {
      ++p;
      spell_word(w, &p);
    } else if (*p == '%') {
      char c = p[1];
      p += c ? 2 : 1;
      if (c == 's') sf_cw_raw(w, va_arg(args, const char *));
      else if (c == 'E') sf_cw_emit(w, va_arg(args, const char *));
      else if (c == 'd') {
        char number[24];
        snprintf(number, sizeof number, "%d", va_arg(args, int));
        sf_cw_raw(w, number);
      } else if (c == 'F') append_float(w, va_arg(args, double));
      else if (c == 'V' || c == 'C') {
        int n = va_arg(args, int);
        char word[16];
        if (n == 1) sf_cw_raw(w, c == 'V' ? "float" : "(");
        else if (n < 2 || n > 4) fail(w, "code template: vector size out of range");
        else {
          snprintf(word, sizeof word, c == 'V' ? "@vec%d" : "@vec%d(", n);
          sf_cw_emit(w, word);
        }
      }
      else if (c == '%') append(w, "%", 1);
      else fail(w, "code template: bad % directive");
    }
  }
}

void sf_cw_emit(sf_code_writer *w, const char *fmt, ...) {
  va_list args;
  va_start(args, fmt);
  sf_cw_emitv(w, fmt, args);
  va_end(args);
}

void sf_cw_const_floats(sf_code_writer *w, const char *indent, const char *name,
                        const double *values, int n) {
  if (w->lang == SF_CODE_C) sf_cw_emit(w, "%sstatic const float %s[%d] = {", indent, name, n);
  else sf_cw_emit(w, "%sconst float %s[%d] = float[%d](", indent, name, n, n);
  for (int i = 0; i < n; ++i) {
    if (i % 4 == 0) sf_cw_emit(w, "\n%s    ", indent);
    sf_cw_emit(w, "%F", values[i]);
    if (i + 1 < n) sf_cw_raw(w, i % 4 == 3 ? "," : ", ");
  }
  sf_cw_emit(w, w->lang == SF_CODE_C ? "};\n" : ");\n");
}
