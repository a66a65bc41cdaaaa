/* Reading validated values from cJSON trees for the input files (SPEC §4,
 * §5): every failure becomes one line "<source>: <key path>: <problem>", the
 * key path naming where in the file the bad value sits ("a.b[2].c"). */
#ifndef SKYFIT_UTIL_JSON_READ_H
#define SKYFIT_UTIL_JSON_READ_H

#include <cjson/cJSON.h>
#include <stddef.h>

#include "util/error.h"
#include "util/read_file.h"

/* Key paths longer than this are cut short in messages, never overflow. */
#define SF_JSON_PATH_LEN 320

/* The file (or string) being read and where its first failure goes. */
typedef struct sf_json_ctx {
  const char *source;
  sf_error *err;
} sf_json_ctx;

/* Records "<source>: <path>: <problem>" as SF_ERR_INPUT; returns SF_ERR_INPUT. */
int sf_json_fail(const sf_json_ctx *c, const char *path, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;

/* "a number", "a string", ...: for "expected X, got Y" messages. */
const char *sf_json_type_name(const cJSON *v);

/* The member named key of obj (exact case), or NULL. */
const cJSON *sf_json_get(const cJSON *obj, const char *key);

/* buf = "prefix.key" ("key" when prefix is empty); buf = "prefix[i]". */
void sf_json_join_key(char *buf, size_t n, const char *prefix, const char *key);
void sf_json_join_index(char *buf, size_t n, const char *prefix, int i);

/* Rejects, key by key in file order, a key outside `allowed` (NULL-terminated)
 * and a key given twice in obj (cJSON keeps both copies, only one is read). */
int sf_json_check_keys(const sf_json_ctx *c, const cJSON *obj, const char *prefix,
                       const char *const *allowed);

/* Rejects a key given twice in any object of the tree below node. */
int sf_json_check_duplicate_keys(const sf_json_ctx *c, const cJSON *node, const char *path);

/* A finite number; -0 is stored as 0 (one value, one canonical text). */
int sf_json_read_finite(const sf_json_ctx *c, const cJSON *v, const char *path, double *out);

/* Parses text (NULL is an error) into *root_out, which the caller deletes.
 * A syntax error is reported at "line L, column C" with the text near it. */
int sf_json_parse(const sf_json_ctx *c, const char *text, cJSON **root_out);

/* How file-level failures of one kind of input file are worded
 * (util/read_file.h). */
typedef sf_file_rules sf_json_file_rules;

/* The whole file as one NUL-terminated string in *text_out (caller frees),
 * by sf_read_file. Rejects a missing or unreadable file, one over
 * rules->max_bytes and one holding a NUL byte (SF_ERR_INPUT); out of
 * memory is SF_ERR_INTERNAL. */
int sf_json_read_file(const char *path, const sf_json_file_rules *rules, char **text_out,
                      sf_error *err);

#endif
