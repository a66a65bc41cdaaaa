/* A stretch that a user's signal must not cut in two: SIGINT, SIGTERM and
 * SIGHUP arriving inside it are held and take effect at its end. For the
 * build's last burst of renames (fit/build_pipeline.c): a Ctrl-C between
 * the headers' renames and the report's had left new headers beside an
 * old report. Process-wide (handlers, not a thread's signal mask: the
 * OpenMP workers would take a blocked signal). One stretch at a time. */
#ifndef SKYFIT_UTIL_SIGNAL_DEFER_H
#define SKYFIT_UTIL_SIGNAL_DEFER_H

#include <signal.h>

typedef struct sf_signal_defer {
  struct sigaction saved[3];
  int installed[3];
} sf_signal_defer;

/* From here the signals are held (those ignored stay ignored). */
void sf_signal_defer_begin(sf_signal_defer *d);
/* The handlers as they were; a signal held meanwhile is raised now. */
void sf_signal_defer_end(sf_signal_defer *d);

#endif
