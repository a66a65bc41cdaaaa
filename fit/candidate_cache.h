/* The fit cache of `skyfit build` (SPEC §5, §11: "a second run with
 * nothing changed reuses the cache"): a fitted model is stored as its
 * weights file (SPEC §8) under CACHE/fits/<model>-<key>.json, the key
 * hashing everything its parameters depend on — the model, the candidate
 * code version, the atmosphere's canonical JSON (through its hash), the
 * scene's domain, the fit options and, for fits to the tables, the tables'
 * resolution. A cached file that fails to load, or is the fit of another
 * atmosphere or domain (sf_cache_fit_belongs), is reported and refitted.
 * Costs (ns per evaluation, fit/candidate_metrics.h) are cached the same
 * way under CACHE/costs/ by codegen/report_evaluate.c, so that a rerun's
 * report is byte-identical. A freshly fitted model is evaluated as loaded
 * back from its weights file, so a fresh run and a cached one compute
 * with the same numbers. A hit marks its file used (sf_cache_entry_used):
 * the build keeps its cache under a size limit, removing the entries unused
 * the longest first (util/cache_prune.h). */
#ifndef SKYFIT_FIT_CANDIDATE_CACHE_H
#define SKYFIT_FIT_CANDIDATE_CACHE_H

#include <stddef.h>

#include "fit/candidate_registry.h"
#include "models/weights_file.h"
#include "util/cache_prune.h"
#include "util/error.h"

/* Bump whenever a change to a candidate's fit changes its parameters. The
 * key also holds a hash of the running executable's bytes
 * (sf_cache_code_identity): fitters and models live in other files that
 * change on their own, so any other skyfit refits and retimes rather than
 * reusing a result the new code would not produce, and a copy of the same
 * one (installed elsewhere) reuses them. Its size and modification time,
 * the key before, had let a rebuild of the same size with a kept time
 * reuse another build's fits, and made a plain copy refit everything. */
#define SF_CANDIDATE_CODE_VERSION "skyfit-candidates 3"

/* SF_CANDIDATE_CODE_VERSION plus the executable's identity: a hash of its
 * bytes, its file's identity where they cannot be read, this process's
 * where neither can. */
void sf_cache_code_identity(char *out, size_t n);

/* The CPU's model name and the processors online (/proc/cpuinfo, sysconf):
 * part of the timings' key (codegen/report_evaluate.c). "" parts when
 * unknown. */
void sf_cache_machine_identity(char *out, size_t n);

/* A key text being built: "name=value;" pairs. */
typedef struct sf_cache_key {
  char text[2048];
} sf_cache_key;

/* Starts a key with the model, the code version, the atmosphere hash and
 * the domain (every number printed %.17g, so equal doubles give equal
 * text). */
void sf_cache_key_begin(sf_cache_key *k, const char *model, const sf_candidate_inputs *in);
void sf_cache_key_add_number(sf_cache_key *k, const char *name, double v);
void sf_cache_key_add_text(sf_cache_key *k, const char *name, const char *v);
/* The table resolution and orders of the build's tables (for fits to them). */
void sf_cache_key_add_tables(sf_cache_key *k, const sf_candidate_inputs *in);

/* CACHE/<sub>/<model>-<16 hex digits of the key's hash>.json, sub one of the
 * cache's folders (SF_CACHE_FITS, SF_CACHE_COSTS: util/cache_prune.h); creates
 * CACHE/<sub>. in->cache_dir NULL: path "" (no caching), SF_OK. */
int sf_cache_path(const char *cache_dir, const char *sub, const char *model, const sf_cache_key *k,
                  char *path, size_t n, sf_error *err);

/* SF_OK if this process may make files in dir (faccessat with its
 * effective ids: a read-only file system or folder, a missing permission);
 * otherwise the reason (sf_write_error_status of the errno), naming the
 * folder and its role ("cache", "weights"). Checked before any fit: a
 * folder that cannot take the fits had made every fit "fail" and be
 * skipped, so a build shipped other models and exited 0. */
int sf_folder_writable(const char *dir, const char *role, sf_error *err);

/* SF_OK if the weights file at path is a fit of model for this atmosphere
 * (its hash) over this domain; SF_ERR_INPUT saying what it is otherwise.
 * A cached fit passes it before use: the key names the file, but a file
 * copied from another project's cache had been used as it was (a Mars
 * sigmoid shipped in a header labelled with Earth's atmosphere). */
int sf_cache_fit_belongs(const char *path, const char *model, const sf_atmosphere *atm,
                         const sf_scene_domain *domain, sf_error *err);
/* The same test of a weights document already loaded (named by its source). */
int sf_cache_weights_belong(const sf_weights *w, const sf_atmosphere *atm, const sf_scene_domain *domain,
                            sf_error *err);

/* 1 when path names an existing regular file. */
int sf_cache_exists(const char *path);

/* Copies src to dst atomically (the weights file of a cached fit into the
 * build's weights folder). */
int sf_copy_file(const char *src, const char *dst, sf_error *err);

/* Copies the weights file src to WORK_DIR/<name>.json and puts that path
 * in dst (n bytes: a candidate's or the report's weights_path). A path
 * longer than n fails with nothing copied, rather than naming a truncated
 * file. */
int sf_copy_weights_to_work_dir(const char *src, const char *work_dir, const char *name, char *dst, size_t n,
                                sf_error *err);

#endif
