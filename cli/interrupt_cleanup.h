/* What a Ctrl-C (or SIGTERM, SIGHUP) of a long command leaves behind:
 * nothing. `skyfit build` writes its outputs under OUT/.staging.PID and
 * temporaries beside its headers and tables (fit/build_staging.h,
 * util/atomic_file.h); killed by a signal, it had left them for the next
 * build to remove, and SPEC §11 wants no partial file at all.
 *
 * The command's work runs in a child process; this one waits. When the
 * child ends by a signal (its own Ctrl-C, or one this process forwards),
 * the cleanup removes what the child left (its PID no longer exists, so
 * the stale-file rules of those modules apply to it), and this process
 * ends by the same signal. A child whose parent dies (SIGKILL) is killed
 * too (Linux). */
#ifndef SKYFIT_CLI_INTERRUPT_CLEANUP_H
#define SKYFIT_CLI_INTERRUPT_CLEANUP_H

typedef void (*sf_cli_cleanup_fn)(void *ctx);

/* Returns in the child (0), which does the work and exits as it would
 * have; or, where no child can be made, in this process (-1: the work runs
 * unsupervised). In this process otherwise never returns: it exits with
 * the child's status, after cleanup(ctx) if the child ended by a signal.
 * Call before any thread is started (OpenMP's pool does not survive a
 * fork). */
int sf_cli_supervise(sf_cli_cleanup_fn cleanup, void *ctx);

/* The files and folders a command writes: where a killed writer's
 * temporaries ("NAME.tmp.PID.XXXXXX", util/atomic_file.h) may be left. The
 * paths are borrowed. */
#define SF_CLI_MAX_OUTPUTS 8
typedef struct sf_cli_outputs {
  const char *files[SF_CLI_MAX_OUTPUTS];     /* each file's own temporaries */
  const char *folders[SF_CLI_MAX_OUTPUTS];   /* any temporary in them (tables, caches) */
  int n_files, n_folders;
} sf_cli_outputs;

/* Adds a file or a folder (NULL or "" ignored; beyond SF_CLI_MAX_OUTPUTS
 * too, which a caller's fixed set never reaches). */
void sf_cli_outputs_add_file(sf_cli_outputs *o, const char *path);
void sf_cli_outputs_add_folder(sf_cli_outputs *o, const char *path);

/* sf_cli_supervise with a cleanup that removes those temporaries: for the
 * commands that write a few known files (fit, codegen, eval from the
 * tables). A SIGTERM of `fit preetham --tables T` had left a table's
 * temporary in T, one of `codegen` a header's. outputs must live until the
 * command ends (the caller's frame: this process never returns). */
int sf_cli_supervise_outputs(const sf_cli_outputs *outputs);

#endif
