/* A command's output file, checked before any work (SPEC §11: bad input
 * exits 2 and writes nothing): it can be written atomically
 * (util/atomic_file.h), and it is none of the run's input files. `fit
 * sigmoid --atmosphere a.json --out a.json` had replaced the atmosphere by
 * the weights, `fit mlp --data t.csv --out t.csv` the training set; an
 * unwritable --out of `fit hosek` had been found after 35 s of fitting. */
#ifndef SKYFIT_CLI_OUTPUT_FILE_CHECK_H
#define SKYFIT_CLI_OUTPUT_FILE_CHECK_H

#include "models/scene_file.h"
#include "util/error.h"

/* The same file: the same path, the same inode of two existing ones, or,
 * for two that do not exist yet, the same name in the same resolved folder
 * ("d.csv" and "./d.csv"). */
int sf_cli_same_file(const char *a, const char *b);

/* The first of files[0..n) (NULL entries skipped) that is the same file
 * as path (sf_cli_same_file), or NULL. */
const char *sf_cli_same_as_any(const char *path, const char *const *files, int n);

/* The first of folders[0..n) (NULL entries skipped) that path lies in, at
 * any depth ("OUT/views/a/b.h" lies in "OUT/views"), each folder on path
 * compared by sf_cli_same_file; NULL when none. */
const char *sf_cli_inside_any(const char *path, const char *const *folders, int n);

/* SF_OK when path (given as option) can be written and is none of the
 * run's other files inputs[0..n) (NULL entries skipped); else SF_ERR_INPUT
 * in err, the message naming the option and the path. */
int sf_cli_output_problem(const char *option, const char *path, const char *const *inputs, int n_inputs,
                          sf_error *err);

/* A fit's input files, which its outputs must not be: the scene file, the
 * atmosphere file the scene names (none for the built-in one) and an
 * --atmosphere file; NULL where there is none. */
void sf_cli_scene_files(const char *scene_path, const char *atmosphere_path, const sf_scene *scene,
                        const char *files[3]);

/* A command whose result is its standard output: 0 once stdout is flushed,
 * else "<command>: writing to stdout failed" on stderr and 1 (a full disk
 * had lost `fit mlp`'s and `fit --samples`' results with exit 0). */
int sf_cli_stdout_written(const char *command);

/* The same, printed: 0, or "<command>: <message>" on stderr and 2. */
int sf_cli_check_output(const char *command, const char *option, const char *path, const char *const *inputs,
                        int n_inputs);

#endif
