/* Table cache (SPEC §6): a table is stored as DIR/<quantity>-<key>.exr where
 * key is a 64-bit FNV-1a hash (then the bijective finaliser sf_hash64_mix)
 * of everything that determines its values. A
 * cached table is never recomputed; a corrupt one is reported and ignored so
 * that the caller recomputes it and stores it over the bad file.
 *
 * Typical use:
 *   sf_table_desc desc = ...;                     (axes, channels, quantity)
 *   sf_table_cache_key(&desc, atm_json, orders, SKYFIT_VERSION, desc.content_hash);
 *   sf_table table; sf_error problem = {0};
 *   if (!sf_table_cache_load(dir, &desc, 0, &table, &problem)) {
 *     if (problem.status) fprintf(stderr, "%s; recomputing\n", problem.message);
 *     sf_table_init(&table, &desc, atm_json, 0, err); ...compute...
 *     sf_table_cache_store(dir, &table, err);
 *   } */
#ifndef SKYFIT_DATA_TABLE_CACHE_H
#define SKYFIT_DATA_TABLE_CACHE_H

#include <stddef.h>
#include "data/table.h"
#include "util/error.h"

/* key (17 bytes: 16 lowercase hex digits + NUL) = hash of: the canonical
 * atmosphere JSON text, desc's quantity, parameterization, axes (name,
 * size, min and max to 17 digits, mapping) and channel names, the number
 * of scattering orders (0 where it does not apply) and code_version (bump
 * it whenever the computation of a table changes). desc->content_hash is
 * not an input, so key may be desc->content_hash itself. */
void sf_table_cache_key(const sf_table_desc *desc, const char *atmosphere_json, int scattering_orders,
                        const char *code_version, char key[17]);

/* DIR/<quantity>-<key>.exr into out (size n). SF_ERR_INPUT if it does not
 * fit, or quantity/key are not file-name safe. */
int sf_table_cache_path(const char *dir, const char *quantity, const char *key, char *out, size_t n,
                        sf_error *err);

/* Looks for the table described by desc (desc->content_hash is the key).
 * Returns 1 and fills *out if a valid file exists whose stored description
 * (quantity, parameterization, axes, channels, hash) equals desc, and marks
 * that file used now (util/cache_prune.h: a build's cache removes the
 * entries unused the longest first). Returns 0
 * with *out empty otherwise; if a file was there but is unusable (damaged,
 * or holds another table) `problem` gets SF_ERR_INPUT and the message
 * "cache file PATH is corrupt: ..."; if there is simply none, `problem` is
 * left untouched. */
int sf_table_cache_load(const char *dir, const sf_table_desc *desc, size_t max_bytes, sf_table *out,
                        sf_error *problem);

/* Writes t (its desc.content_hash must be set) to its cache path, creating
 * dir (and parents) if needed; atomic like sf_table_write_exr. */
int sf_table_cache_store(const char *dir, const sf_table *t, sf_error *err);

#endif
