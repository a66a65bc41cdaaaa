#include "util/json_read.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int sf_json_fail(const sf_json_ctx *c, const char *path, const char *fmt, ...) {
  char problem[900];
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(problem, sizeof problem, fmt, ap);
  va_end(ap);
  sf_fail(c->err, SF_ERR_INPUT, "%s: %s: %s", c->source, path, problem);
  return SF_ERR_INPUT;
}

const char *sf_json_type_name(const cJSON *v) {
  if (cJSON_IsNumber(v)) return "a number";
  if (cJSON_IsString(v)) return "a string";
  if (cJSON_IsArray(v)) return "an array";
  if (cJSON_IsObject(v)) return "an object";
  if (cJSON_IsBool(v)) return "a boolean";
  if (cJSON_IsNull(v)) return "null";
  return "an invalid value";
}

const cJSON *sf_json_get(const cJSON *obj, const char *key) {
  return cJSON_GetObjectItemCaseSensitive(obj, key);
}

static void path_join(char *buf, size_t n, const char *a, const char *sep, const char *b) {
  size_t used = 0;
  const char *parts[3] = {a, sep, b};
  for (int p = 0; p < 3; ++p)
    for (const char *q = parts[p]; *q && used + 1 < n; ++q) buf[used++] = *q;
  buf[used] = '\0';
}

void sf_json_join_key(char *buf, size_t n, const char *prefix, const char *key) {
  path_join(buf, n, prefix, prefix[0] ? "." : "", key);
}

void sf_json_join_index(char *buf, size_t n, const char *prefix, int i) {
  char index[16];
  snprintf(index, sizeof index, "[%d]", i);
  path_join(buf, n, prefix, "", index);
}

int sf_json_check_keys(const sf_json_ctx *c, const cJSON *obj, const char *prefix,
                       const char *const *allowed) {
  for (const cJSON *k = obj->child; k; k = k->next) {
    const char *key = k->string ? k->string : "";
    char path[SF_JSON_PATH_LEN];
    sf_json_join_key(path, sizeof path, prefix, key);
    int known = 0;
    for (int i = 0; allowed[i]; ++i)
      if (strcmp(key, allowed[i]) == 0) known = 1;
    if (!known) {
      char list[512] = "";
      size_t used = 0;
      for (int i = 0; allowed[i] && used < sizeof list; ++i)
        used += (size_t)snprintf(list + used, sizeof list - used, "%s%s", i ? ", " : "",
                                 allowed[i]);
      return sf_json_fail(c, path, "unknown key (allowed here: %s)", list);
    }
    for (const cJSON *e = obj->child; e != k; e = e->next)
      if (e->string && strcmp(e->string, key) == 0)
        return sf_json_fail(c, path, "duplicate key (given twice in the same object)");
  }
  return 0;
}

int sf_json_check_duplicate_keys(const sf_json_ctx *c, const cJSON *node, const char *path) {
  int i = 0;
  for (const cJSON *k = node->child; k; k = k->next, ++i) {
    char kpath[SF_JSON_PATH_LEN];
    if (cJSON_IsObject(node)) {
      sf_json_join_key(kpath, sizeof kpath, path, k->string);
      for (const cJSON *e = node->child; e != k; e = e->next)
        if (strcmp(e->string, k->string) == 0)
          return sf_json_fail(c, kpath, "duplicate key (given twice in the same object)");
    } else {
      sf_json_join_index(kpath, sizeof kpath, path, i);
    }
    if (sf_json_check_duplicate_keys(c, k, kpath)) return SF_ERR_INPUT;
  }
  return 0;
}

int sf_json_read_finite(const sf_json_ctx *c, const cJSON *v, const char *path, double *out) {
  if (!cJSON_IsNumber(v))
    return sf_json_fail(c, path, "expected a number, got %s", sf_json_type_name(v));
  double x = v->valuedouble;
  if (!isfinite(x)) return sf_json_fail(c, path, "not a finite number (too large for a double)");
  *out = x == 0.0 ? 0.0 : x;
  return 0;
}

/* cJSON reports where parsing stopped; people want line and column. */
static int syntax_error(const sf_json_ctx *c, const char *text, const char *stop) {
  if (!stop) stop = text;
  int line = 1;
  const char *line_start = text;
  for (const char *p = text; p < stop && *p; ++p)
    if (*p == '\n') {
      ++line;
      line_start = p + 1;
    }
  char where[64], near[24];
  snprintf(where, sizeof where, "line %d, column %d", line, (int)(stop - line_start) + 1);
  size_t n = 0;
  while (n + 1 < sizeof near && stop[n] && stop[n] != '\n' && stop[n] != '\r') {
    near[n] = (unsigned char)stop[n] < 0x20 ? ' ' : stop[n];
    ++n;
  }
  near[n] = '\0';
  if (n == 0 && *stop == '\0') return sf_json_fail(c, where, "JSON syntax error: unexpected end of input");
  return sf_json_fail(c, where, "JSON syntax error near '%s'", near);
}

int sf_json_parse(const sf_json_ctx *c, const char *text, cJSON **root_out) {
  if (!text) return sf_json_fail(c, "(root)", "no JSON text");
  const char *stop = NULL;
  cJSON *root = cJSON_ParseWithOpts(text, &stop, 1);
  if (!root) return syntax_error(c, text, stop);
  *root_out = root;
  return 0;
}

int sf_json_read_file(const char *path, const sf_json_file_rules *rules, char **text_out,
                      sf_error *err) {
  char *text = NULL;
  size_t len = 0;
  int rc = sf_read_file(path, rules, &text, &len, err);
  if (rc) return rc;
  if (strlen(text) != len) {
    rc = sf_fail(err, SF_ERR_INPUT, "%s: byte %zu: NUL byte in a JSON file", path, strlen(text));
    free(text);
    return rc;
  }
  *text_out = text;
  return 0;
}
