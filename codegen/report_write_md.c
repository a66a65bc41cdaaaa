/* report.md: the report's tables and verdicts as Markdown, and
 * sf_report_write_all (metrics.json, report.md, report.html). */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "codegen/report.h"
#include "models/views_standard.h"
#include "util/atomic_file.h"
#include "util/make_folders.h"
#include "util/path_from_folder.h"

static void num(FILE *f, double v) {
  if (isfinite(v)) fprintf(f, "%.3g", v);
  else fputs("-", f);
}

static void write_md(FILE *f, const sf_report *rep) {
  fprintf(f, "# skyfit fit-quality report: %s\n\n", rep->scene_name);
  fprintf(f, "Atmosphere **%s** (hash %s), %d channels. Domain: h %.4g..%.4g km, mu %.4g..%.4g, mu_s %.4g..%.4g. "
             "Errors on %zu seeded in-domain samples; cost: median of %d runs over %zu inputs, one thread. "
             "Naive 16-step raymarch: %.3g ns (float32), %.3g ns (double) per evaluation, timed in the same run as "
             "every model here (this one, or the earlier one whose timings the cache holds, all of them).\n\n",
          rep->atmosphere_name, rep->atmosphere_hash, rep->n_channels, rep->domain.h_min_km, rep->domain.h_max_km,
          rep->domain.mu_min, rep->domain.mu_max, rep->domain.mu_s_min, rep->domain.mu_s_max,
          rep->options.domain_samples, rep->options.timing_repetitions, rep->options.timing_points,
          rep->naive16_ns_f32, rep->naive16_ns_f64);
  fputs("## Selection\n\n", f);
  for (int q = 0; q < SF_CANDIDATE_N_QUANTITIES; ++q) {
    const sf_report_selection *s = &rep->selection[q];
    if (!s->asked) continue;
    fprintf(f, "- **%s: %s**%s. %s", sf_candidate_quantity_name((sf_candidate_quantity)q),
            s->model >= 0 ? rep->models[s->model].candidate->name : "none",
            s->meets_budget ? "" : " (does NOT meet the budget)", s->reason);
    if (s->emitted_c[0]) fprintf(f, " Emitted: `%s`, `%s`.", s->emitted_c, s->emitted_glsl);
    if (s->emit_note[0]) fprintf(f, " %s", s->emit_note);
    fputs("\n", f);
  }
  for (int q = 0; q < SF_CANDIDATE_N_QUANTITIES; ++q) {
    if (rep->reference[q] < 0) continue;
    fprintf(f, "\n## %s\n\n", q == SF_CANDIDATE_TRANSMITTANCE ? "Transmittance" : "Sky radiance");
    fputs("| model | role | parameters | constant bytes | ns/eval | precision | x naive-16 | RMSE | max abs | mean rel | "
          "rel RMSE | seg RMSE | seg max | seg rel RMSE | budget |\n"
          "|---|---|---:|---:|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---|\n",
          f);
    for (int i = 0; i < rep->n_models; ++i) {
      const sf_report_model *m = &rep->models[i];
      const sf_candidate *c = m->candidate;
      if ((int)c->quantity != q) continue;
      fprintf(f, "| %s%s%s | %s | %ld | %ld | ", m->selected ? "**" : "", c->name, m->selected ? "**" : "",
              sf_candidate_role_name(c->role), c->n_params, c->constant_bytes);
      if (m->has_cost) {
        num(f, m->cost.ns_median);
        fprintf(f, " | %s | ", m->cost.precision_bits == 32 ? "float32" : "double");
        num(f, m->cost_ratio_naive16);
      } else {
        fputs("- | - | -", f);
      }
      fputs(" | ", f);
      if (m->has_errors) {
        num(f, m->errors.rmse); fputs(" | ", f);
        num(f, m->errors.max_abs); fputs(" | ", f);
        num(f, m->errors.mean_rel); fputs(" | ", f);
        num(f, m->errors.rel_rmse); fputs(" | ", f);
        num(f, m->has_segment_errors ? m->segment_errors.rmse : NAN); fputs(" | ", f);
        num(f, m->has_segment_errors ? m->segment_errors.max_abs : NAN); fputs(" | ", f);
        num(f, m->has_segment_errors ? m->segment_errors.rel_rmse : NAN);
        fprintf(f, " | %s |\n", !rep->selection[q].asked ? "not asked"
                                : !m->selectable ? (m->errors_over_valid_part ? "n/a (errors on its valid part*)" : "n/a")
                                : m->meets_budget ? "meets" : "misses");
      } else {
        fputs("reference | | | | | | | |\n", f);
      }
    }
    int on_front = 0;
    for (int i = 0; i < rep->n_models; ++i) {
      const sf_report_model *m = &rep->models[i];
      if ((int)m->candidate->quantity != q || !m->on_front) continue;
      if (on_front++ == 0)
        fprintf(f, "\nPareto front of cost and error among the models that can ship (`plots/%s-cost-error.svg`): ",
                sf_candidate_quantity_name((sf_candidate_quantity)q));
      else
        fputs(", ", f);
      fputs(m->candidate->name, f);
    }
    if (on_front) fputs(".\n", f);
    for (int i = 0; i < rep->n_models; ++i) {
      const sf_report_model *m = &rep->models[i];
      if ((int)m->candidate->quantity != q || !m->errors_over_valid_part) continue;
      fprintf(f, "\n\\* %s is valid on part of the scene's domain only; its errors and its cost are measured there: h %g..%g km, "
                 "mu %.3g..%.3g, mu_s %.3g..%.3g.\n",
              m->candidate->name, m->errors_domain.h_min_km, m->errors_domain.h_max_km, m->errors_domain.mu_min,
              m->errors_domain.mu_max, m->errors_domain.mu_s_min, m->errors_domain.mu_s_max);
    }
    for (int i = 0; i < rep->n_models; ++i) {
      char note[512];
      if ((int)rep->models[i].candidate->quantity != q) continue;
      sf_report_mean_rel_note(&rep->models[i], note, sizeof note);
      if (note[0]) fprintf(f, "\n%s\n", note);
    }
    {
      char text[2048];
      sf_report_segment_text(rep, q, text, sizeof text);
      if (text[0]) fprintf(f, "\n%s\n", text);
      sf_report_segment_note(rep, q, text, sizeof text);
      if (text[0]) fprintf(f, "\n**%s**\n", text);
    }
    if (q == SF_CANDIDATE_SKY_RADIANCE && rep->reference_check.present) {
      char text[2048];
      sf_report_reference_check_text(rep, text, sizeof text);
      fprintf(f, "\n%s\n", text);
    }
    if (!rep->views_rendered) continue;
    const sf_view_def *views;
    int nv = q == SF_CANDIDATE_TRANSMITTANCE ? sf_standard_transmittance_views(&views) : sf_standard_radiance_views(&views);
    sf_paper_table paper;
    if (q == SF_CANDIDATE_TRANSMITTANCE) sf_paper_appendix_d(&paper); else sf_paper_appendix_b(&paper);
    fprintf(f, "\nPer view: our RMSE (mean ΔE2000), and seed 000 App. %s for the same view as an RMSE: the square "
               "root of the paper's figure, a mean squared error though headed RMSE (codegen/report.h).\n\n| view |",
            q == SF_CANDIDATE_TRANSMITTANCE ? "D" : "B");
    int cols = 1;
    for (int i = 0; i < rep->n_models; ++i)
      if ((int)rep->models[i].candidate->quantity == q && rep->models[i].candidate->role != SF_ROLE_REFERENCE) {
        fprintf(f, " %s |", rep->models[i].candidate->name);
        ++cols;
      }
    for (int c = 0; c < paper.n_columns; ++c) fprintf(f, " seed 000 %s |", paper.columns[c]);
    cols += paper.n_columns;
    fputs("\n|", f);
    for (int c = 0; c < cols; ++c) fputs(c ? "---:|" : "---|", f);
    fputs("\n", f);
    for (int v = 0; v < nv; ++v) {
      fprintf(f, "| %s |", views[v].name);
      for (int i = 0; i < rep->n_models; ++i) {
        const sf_report_model *m = &rep->models[i];
        if ((int)m->candidate->quantity != q || m->candidate->role == SF_ROLE_REFERENCE) continue;
        fputs(" ", f);
        if (v < m->n_views && m->views[v].rendered) {
          num(f, m->views[v].rmse); fputs(" (", f); num(f, m->views[v].mean_delta_e); fputs(")", f);
          if (m->views[v].compared_fraction < SF_REPORT_VIEW_WHOLE)
            fprintf(f, " [%.0f %%]", 100.0 * m->views[v].compared_fraction);
        } else {
          fputs("-", f);
        }
        fputs(" |", f);
      }
      int row = sf_paper_row(&paper, views[v].name);
      for (int c = 0; c < paper.n_columns; ++c) {
        fputs(" ", f);
        if (row >= 0) num(f, sf_paper_rmse(&paper, row, c)); else fputs("-", f);
        fputs(" |", f);
      }
      fputs("\n", f);
    }
  }
  if (rep->views_note[0]) fprintf(f, "\n%s\n", rep->views_note);
  if (rep->notes[0]) fprintf(f, "\n## Notes from the build\n\n%s", rep->notes);
  if (rep->spectral4.present) {
    const sf_report_spectral4 *sp = &rep->spectral4;
    char shown[4096];
    sf_path_from_folder(rep->out_dir, sp->weights_path, shown, sizeof shown);
    fprintf(f, "\n## Colour: 4 wavelengths (seed 003 §5.4)\n\nFitted wavelengths %.1f, %.1f, %.1f, %.1f nm with "
               "weights %.1f, %.1f, %.1f, %.1f nm (weights file %s). Colour error against the full spectrum "
               "(360-830 nm), ΔE2000 after exposure and tone mapping:\n\n| method | atmosphere | mean ΔE | p99 ΔE | "
               "max ΔE | samples |\n|---|---|---:|---:|---:|---:|\n",
            sp->lambda_nm[0], sp->lambda_nm[1], sp->lambda_nm[2], sp->lambda_nm[3], sp->weight_nm[0],
            sp->weight_nm[1], sp->weight_nm[2], sp->weight_nm[3], shown);
    for (int a = 0; a < 2; ++a)
      for (int k = 0; k < SF_REPORT_COLOR_METHODS; ++k) {
        fprintf(f, "| %s | %s | ", sp->method[k], a ? "with aerosols" : "without aerosols (fitted)");
        num(f, sp->mean_de[a][k]); fputs(" | ", f);
        num(f, sp->p99_de[a][k]); fputs(" | ", f);
        num(f, sp->max_de[a][k]);
        fprintf(f, " | %.0f |\n", sp->samples[a][k]);
      }
    fprintf(f, "\nLoss (eq. 5.13): spectral4 %.3g, plain RGB 680/550/440 nm %.3g, 4 uniform wavelengths %.3g.\n",
            sp->loss, sp->rgb_loss, sp->uniform_loss);
  }
  /* the same definitions as report.html's closing note */
  fputs("\nRMSE: seed 000 eq. 61 over every sample and channel; rel RMSE: RMSE / RMS of the reference; mean rel: "
        "mean |model - reference| / max(|reference|, 1e-3 RMS). View RMSE on the exposed linear values, ΔE2000 on "
        "the displayed colours (sky: exposure, 1 - exp(-x); transmittance: as shown; CIELAB). Timings are "
        "wall-clock on a shared machine: compare the ratios.\n", f);
  fprintf(f, "\nPictures, the speed-against-error plots and the Pareto fronts: report.html and plots/.%s\n",
          rep->views_rendered ? " Error maps: views/*-error.exr." : "");
}

int sf_report_write_markdown(const sf_report *rep, const char *path, sf_error *err) {
  sf_atomic_file f;
  if (sf_atomic_open(&f, path, err) != SF_OK) return err->status;
  write_md(f.stream, rep);
  return sf_atomic_commit(&f, err);
}

int sf_report_write_all(const sf_report *rep, sf_error *err) {
  char path[SF_REPORT_PATH_LEN + 64];
  snprintf(path, sizeof path, "%s/plots", rep->out_dir);
  if (sf_make_folders(path, "report folder", err) != SF_OK) return err->status;
  for (int q = 0; q < SF_CANDIDATE_N_QUANTITIES; ++q) {
    if (rep->reference[q] < 0) continue;
    int written;
    snprintf(path, sizeof path, "%s/plots/%s-cost-error.svg", rep->out_dir,
             sf_candidate_quantity_name((sf_candidate_quantity)q));
    if (sf_report_write_plot_file(rep, q, path, &written, err) != SF_OK) return err->status;
  }
  snprintf(path, sizeof path, "%s/metrics.json", rep->out_dir);
  if (sf_report_write_json(rep, path, err) != SF_OK) return err->status;
  snprintf(path, sizeof path, "%s/report.md", rep->out_dir);
  if (sf_report_write_markdown(rep, path, err) != SF_OK) return err->status;
  snprintf(path, sizeof path, "%s/report.html", rep->out_dir);
  if (sf_report_write_html(rep, path, err) != SF_OK) return err->status;
  return SF_OK;
}
