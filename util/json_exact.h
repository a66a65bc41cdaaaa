/* Printing JSON whose numbers read back as the very same doubles.
 *
 * cJSON prints a number with 15 significant digits whenever they read back
 * within DBL_EPSILON (relative) of the value, not exactly; a weights file
 * written that way can carry an atmosphere whose hash no longer matches
 * once loaded (SPEC §8), and a table's axis can move by an ulp. These
 * functions print each number with the fewest digits (15, 16 or 17) that
 * strtod turns back into exactly the same double. */
#ifndef SKYFIT_UTIL_JSON_EXACT_H
#define SKYFIT_UTIL_JSON_EXACT_H

#include <stddef.h>

#include <cjson/cJSON.h>

#include "util/error.h"

/* The shortest %.*g form of x (finite) that reads back exactly; returns
 * the length, or -1 if size is too small. */
int sf_json_exact_number(double x, char *buf, size_t size);

/* cJSON_Print (formatted = 1) or cJSON_PrintUnformatted of doc with every
 * finite number printed exactly (a non-finite one prints as cJSON prints it,
 * null: a loader reading the text back refuses it as it would the file);
 * doc is left unchanged. NULL when out of memory. free() the result. */
char *sf_json_print_exact(const cJSON *doc, int formatted);

/* Writes sf_json_print_exact(doc, 1) and a newline to path atomically
 * (util/atomic_file.h). SF_OK, or the error (nothing written). */
int sf_json_write_exact(const cJSON *doc, const char *path, sf_error *err);

#endif
