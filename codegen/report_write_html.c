/* report.html: one self-contained page (inline CSS and SVG, no script),
 * the PNG previews of the views beside it in views/. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "codegen/html_escape.h"
#include "codegen/report.h"
#include "models/views_standard.h"
#include "util/atomic_file.h"
#include "util/path_from_folder.h"

static void esc(FILE *f, const char *s) { sf_html_escape(f, s); }

static void num(FILE *f, double v) {
  if (isfinite(v)) fprintf(f, "%.3g", v);
  else fputs("&ndash;", f);
}


static void model_table(FILE *f, const sf_report *rep, int q) {
  fputs("<table><tr><th>model</th><th>role</th><th>parameters</th><th>constant bytes</th><th>ns / eval</th>"
        "<th>precision</th><th>&times; naive-16</th><th>RMSE</th><th>max abs</th><th>mean rel</th><th>rel RMSE</th>"
        "<th>seg RMSE</th><th>seg max</th><th>seg rel RMSE</th><th>budget</th></tr>\n", f);
  for (int i = 0; i < rep->n_models; ++i) {
    const sf_report_model *m = &rep->models[i];
    const sf_candidate *c = m->candidate;
    if ((int)c->quantity != q) continue;
    fprintf(f, "<tr%s><td title=\"", m->selected ? " class=\"sel\"" : "");
    esc(f, c->description);
    fputs("\"><b>", f);
    esc(f, c->name);
    fputs("</b><br><span class=\"note\">", f);
    esc(f, c->label);
    fprintf(f, "</span></td><td>%s</td><td>%ld</td><td>%ld</td>", sf_candidate_role_name(c->role), c->n_params,
            c->constant_bytes);
    if (m->has_cost) {
      fputs("<td>", f); num(f, m->cost.ns_median);
      fprintf(f, "</td><td>%s</td><td>", m->cost.precision_bits == 32 ? "float32" : "double");
      num(f, m->cost_ratio_naive16); fputs("</td>", f);
    } else {
      fputs("<td>&ndash;</td><td>&ndash;</td><td>&ndash;</td>", f);
    }
    if (m->has_errors) {
      fputs("<td>", f); num(f, m->errors.rmse);
      fputs("</td><td>", f); num(f, m->errors.max_abs);
      fputs("</td><td>", f); num(f, m->errors.mean_rel);
      fputs("</td><td>", f); num(f, m->errors.rel_rmse);
      fputs("</td><td>", f); num(f, m->has_segment_errors ? m->segment_errors.rmse : NAN);
      fputs("</td><td>", f); num(f, m->has_segment_errors ? m->segment_errors.max_abs : NAN);
      fputs("</td><td>", f); num(f, m->has_segment_errors ? m->segment_errors.rel_rmse : NAN);
      fprintf(f, "</td><td>%s</td>", !rep->selection[q].asked ? "not asked"
                                      : !m->selectable ? (m->errors_over_valid_part ? "n/a (errors on its valid part*)" : "n/a")
                                      : m->meets_budget ? "meets" : "misses");
    } else {
      fputs("<td colspan=\"8\">reference</td>", f);
    }
    fputs("</tr>\n", f);
  }
  fputs("</table>\n", f);
  for (int i = 0; i < rep->n_models; ++i) {
    const sf_report_model *m = &rep->models[i];
    if ((int)m->candidate->quantity != q || !m->errors_over_valid_part) continue;
    fprintf(f,
            "<p class=\"note\">* %s is valid on part of the scene's domain only; its errors and its cost are measured there: "
            "h %g..%g km, mu %.3g..%.3g, mu_s %.3g..%.3g.</p>\n",
            m->candidate->name, m->errors_domain.h_min_km, m->errors_domain.h_max_km, m->errors_domain.mu_min,
            m->errors_domain.mu_max, m->errors_domain.mu_s_min, m->errors_domain.mu_s_max);
  }
  for (int i = 0; i < rep->n_models; ++i) {
    char note[512];
    if ((int)rep->models[i].candidate->quantity != q) continue;
    sf_report_mean_rel_note(&rep->models[i], note, sizeof note);
    if (!note[0]) continue;
    fputs("<p class=\"note\">", f);
    esc(f, note);
    fputs("</p>\n", f);
  }
  char text[2048];
  sf_report_segment_text(rep, q, text, sizeof text);
  if (text[0]) {
    fputs("<p class=\"note\">", f);
    esc(f, text);
    fputs("</p>\n", f);
  }
  sf_report_segment_note(rep, q, text, sizeof text);
  if (text[0]) {
    fputs("<p><b>", f);
    esc(f, text);
    fputs("</b></p>\n", f);
  }
}

static void views_section(FILE *f, const sf_report *rep, int q) {
  const sf_view_def *views;
  int nv = q == SF_CANDIDATE_TRANSMITTANCE ? sf_standard_transmittance_views(&views) : sf_standard_radiance_views(&views);
  sf_paper_table paper;
  if (q == SF_CANDIDATE_TRANSMITTANCE) sf_paper_appendix_d(&paper); else sf_paper_appendix_b(&paper);
  /* Per-view figures beside seed 000's. */
  fprintf(f, "<h3>Per view: RMSE (ΔE2000) of ours, and seed 000 App. %s as an RMSE</h3>\n<table><tr><th>view</th>",
          q == SF_CANDIDATE_TRANSMITTANCE ? "D" : "B");
  for (int i = 0; i < rep->n_models; ++i)
    if ((int)rep->models[i].candidate->quantity == q && rep->models[i].candidate->role != SF_ROLE_REFERENCE) {
      fputs("<th>", f); esc(f, rep->models[i].candidate->name); fputs("</th>", f);
    }
  for (int c = 0; c < paper.n_columns; ++c) {
    fputs("<th class=\"paper\">seed 000: ", f); esc(f, paper.columns[c]); fputs("</th>", f);
  }
  fputs("</tr>\n", f);
  for (int v = 0; v < nv; ++v) {
    fprintf(f, "<tr><td>%s</td>", views[v].name);
    for (int i = 0; i < rep->n_models; ++i) {
      const sf_report_model *m = &rep->models[i];
      if ((int)m->candidate->quantity != q || m->candidate->role == SF_ROLE_REFERENCE) continue;
      if (v < m->n_views && m->views[v].rendered) {
        fputs("<td>", f); num(f, m->views[v].rmse); fputs(" (", f); num(f, m->views[v].mean_delta_e); fputs(")", f);
        if (m->views[v].compared_fraction < SF_REPORT_VIEW_WHOLE)
          fprintf(f, " <span class=\"note\">[%.0f %%]</span>", 100.0 * m->views[v].compared_fraction);
        fputs("</td>", f);
      } else {
        fputs("<td>&ndash;</td>", f);
      }
    }
    int row = sf_paper_row(&paper, views[v].name);
    for (int c = 0; c < paper.n_columns; ++c) {
      fputs("<td class=\"paper\">", f);
      if (row >= 0) num(f, sf_paper_rmse(&paper, row, c)); else fputs("&ndash;", f);
      fputs("</td>", f);
    }
    fputs("</tr>\n", f);
  }
  fputs("</table>\n<p class=\"note\">The seed's columns are the square roots of its appendix's figures, which are "
        "mean squared errors though headed RMSE: its Naive column (single scattering only) is 1.2-5.8x the mean square of "
        "the multiple scattering in our views, and as a root it would be 9-64x below it (codegen/report.h). "
        "Seed 000 compares against a path tracer (sky radiance) or a 128-step raymarch "
        "(transmittance) at 1920&times;1080 with its own cameras; ours compares against our reference tables / exact "
        "optical depth, at the view size below, with the cameras of models/views_standard.h. Same views, exposures and "
        "sun irradiance; comparable in order of magnitude, not digit for digit.</p>\n", f);
  /* Pictures. */
  fputs("<h3>Views</h3>\n<table class=\"views\"><tr><th>view</th>", f);
  for (int i = 0; i < rep->n_models; ++i)
    if ((int)rep->models[i].candidate->quantity == q) {
      fputs("<th>", f); esc(f, rep->models[i].candidate->name); fputs("</th>", f);
    }
  fputs("</tr>\n", f);
  for (int v = 0; v < nv; ++v) {
    fprintf(f, "<tr><td>%s<br><span class=\"note\">", views[v].name);
    esc(f, views[v].label);
    fprintf(f, "; exposure %g</span></td>", views[v].exposure);
    for (int i = 0; i < rep->n_models; ++i) {
      const sf_report_model *m = &rep->models[i];
      if ((int)m->candidate->quantity != q) continue;
      if (v < m->n_views && m->views[v].rendered) {
        fprintf(f, "<td><img src=\"%s\" width=\"%d\" height=\"%d\" alt=\"%s %s\"></td>", m->views[v].png,
                rep->options.view_width, rep->options.view_height, m->candidate->name, views[v].name);
      } else {
        fputs("<td class=\"note\">no pixel compared</td>", f);
      }
    }
    fputs("</tr>\n", f);
  }
  fputs("</table>\n", f);
}

static void write_page(FILE *f, const sf_report *rep) {
  fputs("<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>skyfit report: ", f);
  esc(f, rep->scene_name);
  fputs("</title>\n<style>body{font-family:sans-serif;margin:24px;color:#222;background:#fff;max-width:1400px}"
        "table{border-collapse:collapse;margin:8px 0}td,th{border:1px solid #ccc;padding:3px 6px;font-size:13px;"
        "text-align:right}th{background:#f0f0f0}td:first-child{text-align:left}.sel{background:#e6f5e6}"
        ".note{color:#666;font-size:12px}.paper{background:#f7f3ea}.views td{text-align:center}"
        ".verdict{font-size:15px;padding:8px;border-left:4px solid #2a7;background:#f4fbf6}"
        ".miss{border-left-color:#c00;background:#fbf4f4}</style></head><body>\n", f);
  fputs("<h1>skyfit fit-quality report: ", f);
  esc(f, rep->scene_name);
  fputs("</h1>\n<p>Atmosphere <b>", f);
  esc(f, rep->atmosphere_name);
  fprintf(f, "</b> (hash %s), %d channels. Domain: h %.4g&ndash;%.4g km, &mu; %.4g&ndash;%.4g, &mu;<sub>s</sub> "
             "%.4g&ndash;%.4g. Errors on %zu seeded in-domain samples (seed %llu); cost: median of %d runs over "
             "%zu in-domain inputs on one thread; the naive 16-step raymarch took %.3g ns (float32) / %.3g ns "
             "(double) per evaluation, timed in the same run as every model here (this one, or the earlier one whose "
             "timings the cache holds, all of them).</p>\n",
          rep->atmosphere_hash, rep->n_channels, rep->domain.h_min_km, rep->domain.h_max_km, rep->domain.mu_min,
          rep->domain.mu_max, rep->domain.mu_s_min, rep->domain.mu_s_max, rep->options.domain_samples,
          rep->options.seed, rep->options.timing_repetitions, rep->options.timing_points, rep->naive16_ns_f32,
          rep->naive16_ns_f64);
  fputs("<h2>Selection</h2>\n", f);
  for (int q = 0; q < SF_CANDIDATE_N_QUANTITIES; ++q) {
    const sf_report_selection *s = &rep->selection[q];
    if (!s->asked) continue;
    fprintf(f, "<p class=\"verdict%s\"><b>%s: %s</b>. ", s->meets_budget ? "" : " miss",
            sf_candidate_quantity_name((sf_candidate_quantity)q),
            s->model >= 0 ? rep->models[s->model].candidate->name : "none");
    esc(f, s->reason);
    if (s->emitted_c[0]) {
      fputs(" Emitted: ", f); esc(f, s->emitted_c); fputs(", ", f); esc(f, s->emitted_glsl); fputs(".", f);
    }
    if (s->emit_note[0]) { fputs(" ", f); esc(f, s->emit_note); }
    fputs("</p>\n", f);
  }
  for (int q = 0; q < SF_CANDIDATE_N_QUANTITIES; ++q) {
    if (rep->reference[q] < 0) continue;
    fprintf(f, "<h2>%s</h2>\n", q == SF_CANDIDATE_TRANSMITTANCE ? "Transmittance" : "Sky radiance");
    model_table(f, rep, q);
    if (q == SF_CANDIDATE_SKY_RADIANCE && rep->reference_check.present) {
      char text[2048];
      sf_report_reference_check_text(rep, text, sizeof text);
      fputs("<p class=\"note\">", f);
      esc(f, text);
      fputs("</p>\n", f);
    }
    if (sf_report_write_plot(f, rep, q))
      fputs("<p class=\"note\">Orange: analytic baselines; blue: fitted models; grey: table lookup; hollow: a model "
            "that cannot ship (it needs the tables at run time, cannot be emitted or is valid on part of the domain "
            "only), left out of the front. Green line (a green ring for a front of one model): the Pareto front of those that can; dashed red: the scene's "
            "budget; black ring: the selection.</p>\n", f);
    else
      fputs("<p>No model with both a cost and an error to plot.</p>\n", f);
    if (rep->views_rendered) views_section(f, rep, q);
  }
  if (rep->views_note[0]) { fputs("<p>", f); esc(f, rep->views_note); fputs("</p>\n", f); }
  if (rep->notes[0]) {
    fputs("<h2>Notes from the build</h2>\n<pre>", f);
    esc(f, rep->notes);
    fputs("</pre>\n", f);
  }
  if (rep->spectral4.present) {
    const sf_report_spectral4 *sp = &rep->spectral4;
    fprintf(f, "<h2>Colour: 4 wavelengths (seed 003 &sect;5.4)</h2>\n<p>Fitted wavelengths %.1f, %.1f, %.1f, %.1f nm "
               "with weights %.1f, %.1f, %.1f, %.1f nm (weights file <code>",
            sp->lambda_nm[0], sp->lambda_nm[1], sp->lambda_nm[2], sp->lambda_nm[3], sp->weight_nm[0],
            sp->weight_nm[1], sp->weight_nm[2], sp->weight_nm[3]);
    char shown[4096];
    sf_path_from_folder(rep->out_dir, sp->weights_path, shown, sizeof shown);
    esc(f, shown);
    fputs("</code>). Colour error against the full spectrum (360&ndash;830 nm), &Delta;E2000 after exposure and "
          "tone mapping.</p>\n<table><tr><th>method</th><th>atmosphere</th><th>mean &Delta;E</th><th>p99 &Delta;E</th>"
          "<th>max &Delta;E</th><th>samples</th></tr>\n", f);
    for (int a = 0; a < 2; ++a)
      for (int k = 0; k < SF_REPORT_COLOR_METHODS; ++k) {
        fprintf(f, "<tr%s><td>", k == 0 ? " class=\"sel\"" : "");
        esc(f, sp->method[k]);
        fprintf(f, "</td><td>%s</td><td>", a ? "with aerosols" : "without aerosols (fitted)");
        num(f, sp->mean_de[a][k]); fputs("</td><td>", f);
        num(f, sp->p99_de[a][k]); fputs("</td><td>", f);
        num(f, sp->max_de[a][k]);
        fprintf(f, "</td><td>%.0f</td></tr>\n", sp->samples[a][k]);
      }
    fprintf(f, "</table>\n<p class=\"note\">Loss (eq. 5.13): spectral4 %.3g, plain RGB 680/550/440 nm %.3g, 4 uniform "
               "wavelengths %.3g.</p>\n", sp->loss, sp->rgb_loss, sp->uniform_loss);
  }
  fputs("<p class=\"note\">RMSE: seed 000 eq. 61 over every sample and channel; relative RMSE: RMSE / RMS of the "
        "reference; mean rel: mean |model &minus; reference| / max(|reference|, 1e-3 RMS). View RMSE on the exposed "
        "linear values, ΔE2000 on the displayed colours (sky: exposure, 1 &minus; exp(&minus;x); transmittance: as "
        "shown; CIELAB). Timings are wall-clock on a shared machine: compare the ratios.", f);
  fputs(rep->views_rendered ? " Error maps: views/*-error.exr.</p>\n</body></html>\n" : "</p>\n</body></html>\n", f);
}

int sf_report_write_html(const sf_report *rep, const char *path, sf_error *err) {
  sf_atomic_file f;
  if (sf_atomic_open(&f, path, err) != SF_OK) return err->status;
  write_page(f.stream, rep);
  return sf_atomic_commit(&f, err);
}
