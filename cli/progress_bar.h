/* A progress bar with ETA on stderr for long computations (SPEC §11): drawn
 * only when enabled (stderr is a terminal and --quiet was not given),
 * redrawn at most every 0.1 s, one line per stage. Its update function has
 * the signature of sf_progress_fn (data/precompute_options.h). */
#ifndef SKYFIT_CLI_PROGRESS_BAR_H
#define SKYFIT_CLI_PROGRESS_BAR_H

#include <stdio.h>

typedef struct sf_progress_bar {
  int enabled;
  FILE *out;
  char stage[128];
  double stage_start, last_draw;
  int drawn;            /* the current stage's line is on screen */
  const char *note_prefix;   /* sf_progress_bar_note prints "<prefix>: "; NULL: nothing */
} sf_progress_bar;

/* enabled = wanted && isatty(fileno(out)). */
void sf_progress_bar_init(sf_progress_bar *bar, FILE *out, int wanted);
void sf_progress_bar_update(void *bar, const char *stage, double fraction);
/* Ends the current line. */
void sf_progress_bar_finish(sf_progress_bar *bar);
/* A note while the bar runs (the note callback of the table and fit
 * options; ctx is the bar): ends the bar's line, then prints
 * "<note_prefix>: message" on stderr, whether the bar is drawn or not. */
void sf_progress_bar_note(void *bar, const char *message);

#endif
