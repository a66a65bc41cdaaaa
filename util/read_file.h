/* A whole input file in memory, with the messages skyfit's loaders share:
 * "<path>: <where>cannot open <kind>: <why>", "... <kind> too large (over N
 * bytes)", "... cannot read <kind>: <why>". util/json_read.h's JSON files
 * and fit/dataset_csv.h's training sets read through it. */
#ifndef SKYFIT_UTIL_READ_FILE_H
#define SKYFIT_UTIL_READ_FILE_H

#include <stddef.h>

#include "util/error.h"

/* How file-level failures of one kind of input file are worded. */
typedef struct sf_file_rules {
  const char *kind;  /* "atmosphere file": named in the messages */
  const char *where; /* put before the problem: "" or "(file): " */
  size_t max_bytes;  /* a longer file is rejected */
} sf_file_rules;

/* The whole file as one NUL-terminated string in *text_out (caller frees),
 * its length in *len_out (the text may hold NUL bytes of its own: callers
 * that forbid them check). A regular file is read in one piece of its
 * size; otherwise (a pipe) the buffer grows as the file proves longer,
 * reading at most one byte past max_bytes, so a huge input costs no huge
 * allocation before it is rejected. Missing, unreadable or too large:
 * SF_ERR_INPUT; out of memory: SF_ERR_INTERNAL. */
int sf_read_file(const char *path, const sf_file_rules *rules, char **text_out, size_t *len_out, sf_error *err);

#endif
