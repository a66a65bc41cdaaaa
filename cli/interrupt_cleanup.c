#include "cli/interrupt_cleanup.h"

#include <errno.h>
#include <signal.h>
#include <stdio.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include "util/atomic_file.h"
#if defined(__linux__)
#include <sys/prctl.h>
#endif

/* The signals a user stops a command with, forwarded to the child. */
static const int forwarded[] = {SIGINT, SIGTERM, SIGHUP};
#define N_FORWARDED (int)(sizeof forwarded / sizeof *forwarded)

/* The child a signal is forwarded to, 0 once reaped (a handler can reach
 * nothing else; sig_atomic_t, the one type C11 lets it read). */
static volatile sig_atomic_t supervised_child;

static void forward_signal(int sig) {
  int saved = errno;
  if (supervised_child > 0) kill((pid_t)supervised_child, sig);
  errno = saved;
}

static int is_forwarded(int sig) {
  for (int i = 0; i < N_FORWARDED; ++i)
    if (forwarded[i] == sig) return 1;
  return 0;
}

int sf_cli_supervise(sf_cli_cleanup_fn cleanup, void *ctx) {
  /* The forwarded signals wait (blocked) until the handlers are in place:
   * one arriving between the fork and them had ended this process by its
   * default action, and the child (PR_SET_PDEATHSIG) with nothing cleaned.
   * An ignored SIGCHLD (inherited through exec) would let the kernel reap
   * the child, and waitpid could not report how it ended. */
  sigset_t stop, old_mask;
  sigemptyset(&stop);
  for (int i = 0; i < N_FORWARDED; ++i) sigaddset(&stop, forwarded[i]);
  sigprocmask(SIG_BLOCK, &stop, &old_mask);
  signal(SIGCHLD, SIG_DFL);
  fflush(NULL);   /* nothing buffered is written twice */
  pid_t parent = getpid();
  pid_t child = fork();
  if (child <= 0) {
    sigprocmask(SIG_SETMASK, &old_mask, NULL);
    if (child < 0) return -1;
#if defined(__linux__)
    prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (getppid() != parent) _exit(1);   /* the parent died before prctl */
#else
    (void)parent;
#endif
    return 0;
  }
  supervised_child = (sig_atomic_t)child;
  struct sigaction sa;
  sa.sa_handler = forward_signal;
  sigemptyset(&sa.sa_mask);
  sa.sa_flags = SA_RESTART;
  /* A signal this process ignores (a background job's SIGINT, nohup's
   * SIGHUP) the child ignores too: it stays ignored here. */
  for (int i = 0; i < N_FORWARDED; ++i) {
    struct sigaction was;
    if (sigaction(forwarded[i], NULL, &was) == 0 && was.sa_handler != SIG_IGN) sigaction(forwarded[i], &sa, NULL);
  }
  sigprocmask(SIG_SETMASK, &old_mask, NULL);
  int status = 0;
  while (waitpid(child, &status, 0) < 0)
    if (errno != EINTR) {
      fprintf(stderr, "skyfit: waiting for the work process failed\n");
      _exit(1);
    }
  /* no more forwarding, and no second signal during the cleanup */
  sigprocmask(SIG_BLOCK, &stop, NULL);
  supervised_child = 0;
  /* _exit: this process's heap is the child's copy, not to be freed or
   * leak-checked twice, and nothing is left to flush. */
  if (WIFEXITED(status)) _exit(WEXITSTATUS(status));
  int sig = WIFSIGNALED(status) ? WTERMSIG(status) : SIGKILL;
  if (cleanup) cleanup(ctx);
  /* a user's signal ends this process the same way; a crash of the child
   * (its core already dumped) is an exit status, not a second core */
  if (!is_forwarded(sig)) _exit(128 + sig);
  signal(sig, SIG_DFL);
  sigprocmask(SIG_UNBLOCK, &stop, NULL);
  raise(sig);
  _exit(128 + sig);
}

void sf_cli_outputs_add_file(sf_cli_outputs *o, const char *path) {
  if (path && path[0] && o->n_files < SF_CLI_MAX_OUTPUTS) o->files[o->n_files++] = path;
}

void sf_cli_outputs_add_folder(sf_cli_outputs *o, const char *path) {
  if (path && path[0] && o->n_folders < SF_CLI_MAX_OUTPUTS) o->folders[o->n_folders++] = path;
}

static void remove_output_leftovers(void *ctx) {
  const sf_cli_outputs *o = ctx;
  for (int i = 0; i < o->n_files; ++i) sf_atomic_remove_stale(o->files[i]);
  for (int i = 0; i < o->n_folders; ++i) sf_atomic_remove_stale_in(o->folders[i]);
}

int sf_cli_supervise_outputs(const sf_cli_outputs *outputs) {
  return sf_cli_supervise(remove_output_leftovers, (void *)outputs);
}
