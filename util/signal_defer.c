#include "util/signal_defer.h"

#include <stddef.h>

static const int deferred[3] = {SIGINT, SIGTERM, SIGHUP};

/* The first signal held (0: none); a handler can reach nothing else. */
static volatile sig_atomic_t held_signal;

static void hold_signal(int sig) {
  if (held_signal == 0) held_signal = sig;
}

void sf_signal_defer_begin(sf_signal_defer *d) {
  held_signal = 0;
  struct sigaction sa;
  sa.sa_handler = hold_signal;
  sigemptyset(&sa.sa_mask);
  sa.sa_flags = SA_RESTART;
  for (int i = 0; i < 3; ++i) {
    d->installed[i] = sigaction(deferred[i], NULL, &d->saved[i]) == 0 && d->saved[i].sa_handler != SIG_IGN &&
                      sigaction(deferred[i], &sa, NULL) == 0;
  }
}

void sf_signal_defer_end(sf_signal_defer *d) {
  for (int i = 0; i < 3; ++i)
    if (d->installed[i]) sigaction(deferred[i], &d->saved[i], NULL);
  int sig = held_signal;
  held_signal = 0;
  if (sig != 0) raise(sig);
}
