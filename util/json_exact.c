#include "util/json_exact.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "util/atomic_file.h"

int sf_json_exact_number(double x, char *buf, size_t size) {
  int n = -1;
  for (int digits = 15; digits <= 17; ++digits) {
    n = snprintf(buf, size, "%.*g", digits, x);
    if (n < 0 || (size_t)n >= size) return -1;
    if (strtod(buf, NULL) == x) break;   /* 17 digits always round-trip */
  }
  return n;
}

/* Replaces every number below node with a raw item holding its exact text. */
static int numbers_to_exact_raw(cJSON *node) {
  for (cJSON *child = node->child; child;) {
    cJSON *next = child->next;
    if (cJSON_IsNumber(child) && isfinite(child->valuedouble)) {
      char text[40];
      if (sf_json_exact_number(child->valuedouble, text, sizeof text) < 0) return -1;
      cJSON *raw = cJSON_CreateRaw(text);
      if (!raw) return -1;
      /* Replacing by pointer keeps no key: the raw item takes the number's. */
      raw->string = child->string;
      raw->type |= child->type & cJSON_StringIsConst;
      child->string = NULL;
      if (!cJSON_ReplaceItemViaPointer(node, child, raw)) {
        cJSON_Delete(raw);
        return -1;
      }
    } else if (numbers_to_exact_raw(child) != 0) {
      return -1;
    }
    child = next;
  }
  return 0;
}

char *sf_json_print_exact(const cJSON *doc, int formatted) {
  cJSON *copy = cJSON_Duplicate(doc, 1);
  if (!copy) return NULL;
  char *text = NULL;
  if (cJSON_IsNumber(copy) && isfinite(copy->valuedouble)) {
    char number[40];
    if (sf_json_exact_number(copy->valuedouble, number, sizeof number) >= 0) {
      text = malloc(sizeof number);
      if (text) snprintf(text, sizeof number, "%s", number);
    }
  } else if (numbers_to_exact_raw(copy) == 0) {
    text = formatted ? cJSON_Print(copy) : cJSON_PrintUnformatted(copy);
  }
  cJSON_Delete(copy);
  return text;
}

int sf_json_write_exact(const cJSON *doc, const char *path, sf_error *err) {
  char *text = sf_json_print_exact(doc, 1);
  if (!text) return sf_fail(err, SF_ERR_INTERNAL, "%s: out of memory printing JSON", path);
  sf_atomic_file f;
  int status = sf_atomic_open(&f, path, err);
  if (status == SF_OK) {
    fputs(text, f.stream);
    fputc('\n', f.stream);
    status = sf_atomic_commit(&f, err);
  }
  free(text);
  return status;
}
