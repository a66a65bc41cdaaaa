/* One emitted file (SPEC §9): the header comment naming, for every model in
 * it, the atmosphere, its hash, the domain and the measured error; the
 * vector types and shared helpers the models use (and only those); then
 * each model's functions. The same parts give the C header and the GLSL
 * file, with the same function names and signatures. The text depends on
 * nothing but the parts: identical input, byte-identical output. */
#ifndef SKYFIT_CODEGEN_CODEGEN_FILE_H
#define SKYFIT_CODEGEN_CODEGEN_FILE_H

#include "codegen/code_writer.h"
#include "models/scene_file.h"
#include "util/atomic_file.h"
#include "util/error.h"

#define SF_CODEGEN_TEXT_LEN 1024

typedef struct sf_codegen_part {
  char name[64];                      /* function prefix: skyfit_<name>_... */
  char quantity[64];                  /* "transmittance", "sky_radiance", ... */
  char summary[SF_CODEGEN_TEXT_LEN];  /* what the model is, one line */
  char atmosphere_name[96];
  char atmosphere_hash[17];
  sf_scene_domain domain;
  /* The scene's highest viewer where it lies above domain.h_max_km (the
   * top of the atmosphere: the models start such a viewer's ray where it
   * enters, so their errors are those at the top); 0: none. */
  double viewer_max_km;
  char error[SF_CODEGEN_TEXT_LEN];    /* the measured error, one line */
  /* Writes the model's functions into w. */
  void (*emit)(sf_code_writer *w, const void *model);
  const void *model;
} sf_codegen_part;

/* The whole file named file_name (no folders; e.g. "sky.h") in lang;
 * *text is malloc'd (caller frees). The include guard is
 * SKYFIT_GENERATED_<BASE>_<HASH>_H / _GLSL by lang (BASE the name without
 * its extension, upper-cased, other characters as '_'; HASH 16 hex digits
 * of the FNV-1a of the models' code, so two different headers of one name
 * never share it). prefix (NULL: "skyfit") begins every name the file
 * defines, functions, types and macros (PREFIX_ upper-cased): two scenes'
 * headers with two prefixes live in one program. SF_ERR_INPUT when a
 * model cannot be written (a non-finite constant), two parts share a
 * name, or the prefix is not a valid one. */
int sf_codegen_render(const sf_codegen_part *parts, int n_parts, sf_code_lang lang,
                      const char *file_name, const char *prefix, char **text, sf_error *err);
/* A prefix of emitted names: 1 to 32 of [a-z0-9_], starting with a
 * letter; SF_ERR_INPUT naming it otherwise. */
int sf_codegen_prefix_check(const char *prefix, sf_error *err);

/* Whether the pair can be written there (either path may be NULL): two
 * distinct paths, neither a folder, their folders writable (SF_ERR_INPUT
 * naming the path otherwise). Writes nothing; sf_codegen_prepare_files
 * checks it first, and a caller may before long work. */
int sf_codegen_check_files(const char *c_path, const char *glsl_path, sf_error *err);

/* The pair written to temporaries beside c_path and glsl_path (either may
 * be NULL), not yet in place: sf_codegen_commit_files renames them into
 * place, sf_codegen_abort_files removes them. Lets a caller put them in
 * place together with its other outputs (fit/build_staging.h). On failure
 * nothing is left. */
typedef struct sf_codegen_files {
  sf_atomic_file file[2];   /* C, GLSL */
  int open[2];
} sf_codegen_files;
int sf_codegen_prepare_files(const sf_codegen_part *parts, int n_parts, const char *c_path, const char *glsl_path,
                             const char *prefix, sf_codegen_files *out, sf_error *err);
int sf_codegen_commit_files(sf_codegen_files *f, sf_error *err);
void sf_codegen_abort_files(sf_codegen_files *f);

/* Writes the C header to c_path and the GLSL to glsl_path, exactly those
 * paths (either may be NULL), atomically as a pair: both rendered and
 * written to temporaries before either is renamed into place, so on
 * failure neither file is touched, and a user's signal waits until both
 * renames are done (util/signal_defer.h; not inside another such stretch:
 * a caller holding one calls sf_codegen_commit_files). */
int sf_codegen_write_files(const sf_codegen_part *parts, int n_parts, const char *c_path, const char *glsl_path,
                           const char *prefix, sf_error *err);

/* sf_codegen_write_files to DIR/BASE.h and/or DIR/BASE.glsl; BASE a file
 * name without folders, not empty. */
int sf_codegen_write(const sf_codegen_part *parts, int n_parts, int want_c, int want_glsl,
                     const char *dir, const char *base, const char *prefix, sf_error *err);

#endif
