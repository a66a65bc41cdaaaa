/* The speed-against-error plot of a quantity (SPEC §12): log-log cost (x:
 * ratio to the naive 16-step raymarch) against error (y: the budget
 * metric), the Pareto front of the models that can ship (report_select.c
 * marks them) and the scene's budget, as one SVG element: inline in
 * report.html and, standalone, in DIR/plots/. */
#include <math.h>
#include <stdio.h>

#include "codegen/html_escape.h"
#include "codegen/report.h"
#include "util/atomic_file.h"

enum { MAX_POINTS = 256 };

/* A model of quantity q with a cost and an error to plot (log axes). */
static int plottable(const sf_report_model *m, int q) {
  return (int)m->candidate->quantity == q && m->has_cost && m->has_errors && m->cost_ratio_naive16 > 0.0 &&
         m->budget_metric > 0.0 && isfinite(m->cost_ratio_naive16) && isfinite(m->budget_metric);
}

int sf_report_plot_has_points(const sf_report *rep, int q) {
  if (rep->reference[q] < 0) return 0;
  for (int i = 0; i < rep->n_models; ++i)
    if (plottable(&rep->models[i], q)) return 1;
  return 0;
}

int sf_report_write_plot(FILE *f, const sf_report *rep, int q) {
  int n = 0;
  double cost[MAX_POINTS], error[MAX_POINTS];
  int idx[MAX_POINTS];
  for (int i = 0; i < rep->n_models && n < MAX_POINTS; ++i) {
    const sf_report_model *m = &rep->models[i];
    if (!plottable(m, q)) continue;
    cost[n] = m->cost_ratio_naive16;
    error[n] = m->budget_metric;
    idx[n++] = i;
  }
  if (n == 0) return 0;
  const sf_report_selection *sel = &rep->selection[q];
  double x0 = INFINITY, x1 = -INFINITY, y0 = log10(sel->budget), y1 = log10(sel->budget);
  for (int i = 0; i < n; ++i) {
    x0 = fmin(x0, log10(cost[i])); x1 = fmax(x1, log10(cost[i]));
    y0 = fmin(y0, log10(error[i])); y1 = fmax(y1, log10(error[i]));
  }
  x0 = floor(x0 - 0.2); x1 = ceil(x1 + 0.2); y0 = floor(y0 - 0.2); y1 = ceil(y1 + 0.2);
  /* At most 24 decades per axis (a wildly wrong model would squash the
   * rest); points beyond are drawn on the edge. */
  x0 = fmax(x0, x1 - 24.0); y0 = fmax(y0, y1 - 24.0);
  for (int i = 0; i < n; ++i) {
    cost[i] = fmax(cost[i], pow(10.0, x0));
    error[i] = fmax(error[i], pow(10.0, y0));
  }
  const double W = 640, H = 380, L = 70, R = 20, T = 20, B = 50;
  #define PX(v) (L + ((v) - x0) / (x1 - x0) * (W - L - R))
  #define PY(v) (T + (y1 - (v)) / (y1 - y0) * (H - T - B))
  fprintf(f, "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%g\" height=\"%g\" viewBox=\"0 0 %g %g\" "
             "role=\"img\" aria-label=\"cost against error\">\n", W, H, W, H);
  fprintf(f, "<rect x=\"0\" y=\"0\" width=\"%g\" height=\"%g\" fill=\"#fff\"/>\n", W, H);
  for (double d = x0; d <= x1 + 1e-9; d += 1.0)
    fprintf(f, "<line x1=\"%.1f\" y1=\"%g\" x2=\"%.1f\" y2=\"%g\" stroke=\"#ddd\"/><text x=\"%.1f\" y=\"%g\" "
               "font-size=\"11\" text-anchor=\"middle\">1e%g</text>\n", PX(d), T, PX(d), H - B, PX(d), H - B + 15, d);
  for (double d = y0; d <= y1 + 1e-9; d += 1.0)
    fprintf(f, "<line x1=\"%g\" y1=\"%.1f\" x2=\"%g\" y2=\"%.1f\" stroke=\"#ddd\"/><text x=\"%g\" y=\"%.1f\" "
               "font-size=\"11\" text-anchor=\"end\">1e%g</text>\n", L, PY(d), W - R, PY(d), L - 5, PY(d) + 4, d);
  fprintf(f, "<text x=\"%g\" y=\"%g\" font-size=\"12\" text-anchor=\"middle\">cost: ns per evaluation / naive "
             "16-step raymarch (log)</text>\n", (L + W - R) / 2, H - 12);
  fprintf(f, "<text x=\"14\" y=\"%g\" font-size=\"12\" text-anchor=\"middle\" transform=\"rotate(-90 14 %g)\">%s "
             "(log)</text>\n", (T + H - B) / 2, (T + H - B) / 2, q == SF_CANDIDATE_TRANSMITTANCE ? "RMSE" : "relative RMSE");
  double by = PY(log10(sel->budget));
  fprintf(f, "<line x1=\"%g\" y1=\"%.1f\" x2=\"%g\" y2=\"%.1f\" stroke=\"#c00\" stroke-dasharray=\"6 4\"/>"
             "<text x=\"%g\" y=\"%.1f\" font-size=\"11\" fill=\"#c00\" text-anchor=\"end\">budget %.3g</text>\n",
          L, by, W - R, by, W - R - 4, by - 4, sel->budget);
  /* The front, in order of cost. */
  int order[MAX_POINTS], nf = 0;
  for (int i = 0; i < n; ++i)
    if (rep->models[idx[i]].on_front) order[nf++] = i;
  for (int a = 1; a < nf; ++a)
    for (int b = a; b > 0 && cost[order[b]] < cost[order[b - 1]]; --b) {
      int t = order[b]; order[b] = order[b - 1]; order[b - 1] = t;
    }
  if (nf > 1) {
    fputs("<polyline fill=\"none\" stroke=\"#2a7\" stroke-width=\"2\" points=\"", f);
    for (int a = 0; a < nf; ++a) fprintf(f, "%.1f,%.1f ", PX(log10(cost[order[a]])), PY(log10(error[order[a]])));
    fputs("\"/>\n", f);
  } else if (nf == 1) {   /* a front of one model: a green ring (it had not been marked at all) */
    fprintf(f, "<circle cx=\"%.1f\" cy=\"%.1f\" r=\"11\" fill=\"none\" stroke=\"#2a7\" stroke-width=\"2\"/>\n",
            PX(log10(cost[order[0]])), PY(log10(error[order[0]])));
  }
  for (int i = 0; i < n; ++i) {
    const sf_report_model *m = &rep->models[idx[i]];
    const char *color = m->candidate->role == SF_ROLE_FITTED ? "#1f5fbf" : m->candidate->role == SF_ROLE_LOOKUP ? "#888" : "#d80";
    fprintf(f, "<circle cx=\"%.1f\" cy=\"%.1f\" r=\"%d\" fill=\"%s\" stroke=\"%s\" stroke-width=\"2\"/>",
            PX(log10(cost[i])), PY(log10(error[i])), m->selected ? 7 : 5, m->selectable ? color : "#fff",
            m->selected ? "#000" : color);
    fprintf(f, "<text x=\"%.1f\" y=\"%.1f\" font-size=\"11\">", PX(log10(cost[i])) + 8, PY(log10(error[i])) - 6);
    sf_html_escape(f, m->candidate->name);
    fputs(m->selected ? " (selected)" : "", f);
    fputs("</text>\n", f);
  }
  fputs("</svg>\n", f);
  #undef PX
  #undef PY
  return 1;
}

int sf_report_write_plot_file(const sf_report *rep, int q, const char *path, int *written, sf_error *err) {
  *written = 0;
  sf_atomic_file f;
  if (sf_atomic_open(&f, path, err) != SF_OK) return err->status;
  fputs("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n", f.stream);
  if (!sf_report_write_plot(f.stream, rep, q)) {
    sf_atomic_abort(&f);
    return SF_OK;
  }
  *written = 1;
  return sf_atomic_commit(&f, err);
}
