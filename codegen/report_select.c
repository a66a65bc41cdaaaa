/* sf_report_select: the cheapest candidate within the scene's budget, per
 * quantity (SPEC §5), and the reasons in words. Cost is compared as the
 * ratio to the naive 16-step raymarch at the same precision, so a model
 * timed in double and one timed in float32 are put on one scale. Costs
 * within SF_REPORT_COST_TIE of the cheapest's are a tie, which the smaller
 * error breaks: timings that close are the machine's noise (fresh builds
 * of one scene had emitted either flat or chapman, which in the default
 * build cost 0.253 and 0.267 of the raymarch, Chapman 3.4x the more
 * accurate). */
#include "codegen/report.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "util/str_append.h"

static const char *why_not_selectable(const sf_report_model *m) {
  const sf_candidate *c = m->candidate;
  if (c->role == SF_ROLE_REFERENCE) return "it is the reference";
  if (c->role == SF_ROLE_LOOKUP) return "it needs the reference tables at run time";
  if (!c->emit) return "it cannot be emitted as code";
  if (!m->valid_over_domain) return "it is not valid over the whole scene domain";
  if (!m->has_errors || m->errors.n_values == 0) return "it was not measured";
  if (m->non_finite) return "it gave non-finite values";
  if (!m->has_cost) return "its cost was not measured";
  return NULL;
}

/* The Pareto front of cost and error among the models of quantity q that
 * can ship (a table lookup or a model valid on part of the domain only
 * had pushed the selection off it). */
static void mark_front(sf_report *rep, int q) {
  int n = 0;
  for (int i = 0; i < rep->n_models; ++i) {
    sf_report_model *m = &rep->models[i];
    if ((int)m->candidate->quantity != q) continue;
    m->on_front = 0;
    if (m->selectable && isfinite(m->budget_metric) && isfinite(m->cost_ratio_naive16)) ++n;
  }
  if (n == 0) return;
  double *cost = malloc(sizeof *cost * (size_t)n), *error = malloc(sizeof *error * (size_t)n);
  int *idx = malloc(sizeof *idx * (size_t)n), *front = malloc(sizeof *front * (size_t)n);
  if (cost && error && idx && front) {
    int k = 0;
    for (int i = 0; i < rep->n_models; ++i) {
      const sf_report_model *m = &rep->models[i];
      if ((int)m->candidate->quantity != q || !m->selectable || !isfinite(m->budget_metric) ||
          !isfinite(m->cost_ratio_naive16))
        continue;
      cost[k] = m->cost_ratio_naive16;
      error[k] = m->budget_metric;
      idx[k++] = i;
    }
    sf_pareto_front(n, cost, error, front);
    for (int k2 = 0; k2 < n; ++k2) rep->models[idx[k2]].on_front = front[k2];
  }
  free(cost);
  free(error);
  free(idx);
  free(front);
}

void sf_report_select(sf_report *rep, const sf_scene *scene) {
  for (int q = 0; q < SF_CANDIDATE_N_QUANTITIES; ++q) {
    sf_report_selection *sel = &rep->selection[q];
    memset(sel, 0, sizeof *sel);
    sel->model = -1;
    unsigned flag = q == SF_CANDIDATE_TRANSMITTANCE ? SF_QUANTITY_TRANSMITTANCE : SF_QUANTITY_SKY_RADIANCE;
    sel->asked = (scene->quantities & flag) != 0;
    sel->metric = q == SF_CANDIDATE_TRANSMITTANCE ? "rmse" : "rel_rmse";
    sel->budget = q == SF_CANDIDATE_TRANSMITTANCE ? scene->transmittance_rmse_budget
                                                  : scene->sky_radiance_rel_rmse_budget;
    int best_within = -1, best_error = -1, n_meet = 0, n_selectable = 0;
    for (int i = 0; i < rep->n_models; ++i) {
      sf_report_model *m = &rep->models[i];
      if ((int)m->candidate->quantity != q) continue;
      m->budget_metric = q == SF_CANDIDATE_TRANSMITTANCE ? m->errors.rmse : m->errors.rel_rmse;
      m->selectable = why_not_selectable(m) == NULL;
      m->meets_budget = m->has_errors && m->non_finite == 0 && m->budget_metric <= sel->budget;
      m->selected = 0;
      if (!m->selectable) continue;
      ++n_selectable;
      if (best_error < 0 || m->budget_metric < rep->models[best_error].budget_metric) best_error = i;
      if (!m->meets_budget) continue;
      ++n_meet;
      if (best_within < 0 || m->cost_ratio_naive16 < rep->models[best_within].cost_ratio_naive16) best_within = i;
    }
    if (!sel->asked) {
      snprintf(sel->reason, sizeof sel->reason, "The scene does not ask for %s; nothing is selected.",
               sf_candidate_quantity_name((sf_candidate_quantity)q));
      continue;
    }
    snprintf(sel->reason, sizeof sel->reason, "Budget: %s %s <= %.3g over the scene domain. ",
             sf_candidate_quantity_name((sf_candidate_quantity)q),
             q == SF_CANDIDATE_TRANSMITTANCE ? "RMSE" : "relative RMSE", sel->budget);
    sf_str_append(sel->reason, sizeof sel->reason, "%d candidate(s) may ship, %d meet the budget", n_selectable,
                  n_meet);
    int listed = 0;
    for (int i = 0; i < rep->n_models; ++i) {
      const sf_report_model *m = &rep->models[i];
      if ((int)m->candidate->quantity != q || !m->selectable || !m->meets_budget) continue;
      sf_str_append(sel->reason, sizeof sel->reason, "%s%s (%.3g, %.3gx naive-16)", listed++ ? ", " : ": ",
                    m->candidate->name, m->budget_metric, m->cost_ratio_naive16);
    }
    sf_str_append(sel->reason, sizeof sel->reason, ". ");
    /* the tie: the most accurate of those within SF_REPORT_COST_TIE of the
     * cheapest's cost */
    int cheapest = best_within;
    for (int i = 0; best_within >= 0 && i < rep->n_models; ++i) {
      const sf_report_model *m = &rep->models[i];
      if ((int)m->candidate->quantity != q || !m->selectable || !m->meets_budget) continue;
      if (m->cost_ratio_naive16 <= (1.0 + SF_REPORT_COST_TIE) * rep->models[cheapest].cost_ratio_naive16 &&
          m->budget_metric < rep->models[best_within].budget_metric)
        best_within = i;
    }
    if (best_within >= 0) {
      sel->model = best_within;
      sel->meets_budget = 1;
      const sf_report_model *m = &rep->models[best_within];
      if (best_within == cheapest)
        sf_str_append(sel->reason, sizeof sel->reason,
                      "Selected %s: the cheapest of those that meet it (%.3g ns per evaluation, %.3gx the naive "
                      "16-step raymarch; %s %.3g). ",
                      m->candidate->name, m->cost.ns_median, m->cost_ratio_naive16, sel->metric, m->budget_metric);
      else
        sf_str_append(sel->reason, sizeof sel->reason,
                      "Selected %s: the most accurate of those that meet it within %.0f %% of the cheapest's "
                      "cost, %s's (%.3g ns per evaluation, %.3gx the naive 16-step raymarch against %.3gx; %s "
                      "%.3g against %.3g). ",
                      m->candidate->name, 100.0 * SF_REPORT_COST_TIE, rep->models[cheapest].candidate->name,
                      m->cost.ns_median, m->cost_ratio_naive16, rep->models[cheapest].cost_ratio_naive16, sel->metric,
                      m->budget_metric, rep->models[cheapest].budget_metric);
    } else if (best_error >= 0) {
      sel->model = best_error;
      const sf_report_model *m = &rep->models[best_error];
      sf_str_append(sel->reason, sizeof sel->reason,
                    "NO MODEL MEETS THE BUDGET. Selected the best available instead: %s, with the smallest error "
                    "(%s %.3g, %.3gx the budget; %.3gx naive-16 cost). ",
                    m->candidate->name, sel->metric, m->budget_metric, m->budget_metric / sel->budget,
                    m->cost_ratio_naive16);
    } else {
      sf_str_append(sel->reason, sizeof sel->reason, "No candidate can ship for this quantity. ");
    }
    int others = 0;
    for (int i = 0; i < rep->n_models; ++i) {
      const sf_report_model *m = &rep->models[i];
      if ((int)m->candidate->quantity != q) continue;
      const char *why = why_not_selectable(m);
      if (why && m->candidate->role != SF_ROLE_REFERENCE)
        sf_str_append(sel->reason, sizeof sel->reason, "%s%s: %s", others++ ? "; " : "Not eligible: ",
                      m->candidate->name, why);
    }
    if (others) sf_str_append(sel->reason, sizeof sel->reason, ".");
    /* A fitted model whose error exceeds the reference's RMS did worse
     * than a black sky: its fit failed (Hosek's on --quick's few samples
     * has reached a relative RMSE of 300), which "misses" understates. */
    for (int i = 0; i < rep->n_models; ++i) {
      const sf_report_model *m = &rep->models[i];
      if ((int)m->candidate->quantity == q && m->candidate->role == SF_ROLE_FITTED && m->has_errors &&
          m->errors.rel_rmse > 1.0)
        sf_str_append(sel->reason, sizeof sel->reason,
                      "%s%s FAILED: its relative RMSE is %.3g, an error larger than the reference itself.",
                      others ? " " : "", m->candidate->name, m->errors.rel_rmse);
    }
    if (sel->model >= 0) {
      sel->meets_budget = rep->models[sel->model].meets_budget;
      rep->models[sel->model].selected = 1;
    }
    mark_front(rep, q);
  }
}
