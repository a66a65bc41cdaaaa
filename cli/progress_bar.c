#include "cli/progress_bar.h"
#include "util/clock.h"

#include <string.h>
#include <time.h>
#include <unistd.h>

void sf_progress_bar_init(sf_progress_bar *bar, FILE *out, int wanted) {
  memset(bar, 0, sizeof *bar);
  bar->out = out;
  bar->enabled = wanted && isatty(fileno(out));
}

static void draw(sf_progress_bar *bar, double fraction, double t) {
  enum { WIDTH = 30 };
  int filled = (int)(fraction * WIDTH + 0.5);
  char cells[WIDTH + 1];
  for (int i = 0; i < WIDTH; ++i) cells[i] = i < filled ? '#' : '.';
  cells[WIDTH] = '\0';
  double elapsed = t - bar->stage_start;
  char eta[32] = "";
  if (fraction >= 1.0)
    snprintf(eta, sizeof eta, "%.1f s", elapsed);
  else if (fraction > 0.01 && elapsed > 0.5)
    snprintf(eta, sizeof eta, "ETA %.0f s", elapsed * (1.0 - fraction) / fraction);
  fprintf(bar->out, "\r  %-48.48s [%s] %3.0f%% %-12s", bar->stage, cells, 100.0 * fraction, eta);
  fflush(bar->out);
  bar->drawn = 1;
  bar->last_draw = t;
}

void sf_progress_bar_update(void *ctx, const char *stage, double fraction) {
  sf_progress_bar *bar = ctx;
  if (!bar->enabled) return;
  double t = sf_wall_seconds();
  if (strncmp(stage, bar->stage, sizeof bar->stage - 1) != 0) {
    if (bar->drawn) fputc('\n', bar->out);
    snprintf(bar->stage, sizeof bar->stage, "%s", stage);
    bar->stage_start = t;
    bar->drawn = 0;
    draw(bar, fraction, t);
    return;
  }
  if (fraction >= 1.0 || t - bar->last_draw >= 0.1) draw(bar, fraction, t);
}

void sf_progress_bar_finish(sf_progress_bar *bar) {
  if (bar->enabled && bar->drawn) fputc('\n', bar->out);
  bar->drawn = 0;
  bar->stage[0] = '\0';
}

void sf_progress_bar_note(void *ctx, const char *message) {
  sf_progress_bar *bar = ctx;
  sf_progress_bar_finish(bar);
  if (bar->note_prefix) fprintf(stderr, "%s: %s\n", bar->note_prefix, message);
  else fprintf(stderr, "%s\n", message);
}
