/* The selection and the Pareto front (codegen/report_select.c, SPEC §5,
 * §12) on made-up figures: the cheapest model that meets the budget among
 * those that can ship, costs within SF_REPORT_COST_TIE of it a tie that
 * the smaller error breaks; the front only of those (a cheaper, better table
 * lookup must not push the selection off it); the best available, said
 * so, when none meets the budget; a fitted model whose error exceeds the
 * reference's RMS flagged as failed; a quantity the scene does not ask for
 * gets no selection. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "codegen/report.h"

static void emit_nothing(struct sf_code_writer *w, const void *model) {
  (void)w;
  (void)model;
}

typedef struct fake {
  const char *name;
  sf_candidate_role role;
  int emits, valid;
  double ratio, rmse, rel_rmse;
} fake;

static void fill(sf_report *rep, sf_candidate *cands, const fake *f, int n) {
  memset(rep, 0, sizeof *rep);
  rep->n_models = n;
  rep->models = calloc((size_t)n, sizeof *rep->models);
  for (int i = 0; i < n; ++i) {
    sf_candidate_init(&cands[i], SF_CANDIDATE_TRANSMITTANCE, f[i].role, f[i].name, f[i].name);
    cands[i].emit = f[i].emits ? emit_nothing : NULL;
    sf_report_model *m = &rep->models[i];
    m->candidate = &cands[i];
    m->valid_over_domain = f[i].valid;
    m->has_errors = 1;
    m->errors.n_values = 100;
    m->errors.rmse = f[i].rmse;
    m->errors.rel_rmse = f[i].rel_rmse;
    m->has_cost = 1;
    m->cost.ns_median = 100.0 * f[i].ratio;
    m->cost_ratio_naive16 = f[i].ratio;
  }
  rep->reference[SF_CANDIDATE_TRANSMITTANCE] = 0;
  rep->reference[SF_CANDIDATE_SKY_RADIANCE] = -1;
}

/* How often needle occurs in the transmittance plot of rep. */
static int plot_front_marks(const sf_report *rep, const char *needle) {
  char *text = NULL;
  size_t size = 0;
  FILE *f = open_memstream(&text, &size);
  if (!f) return -1;
  int drawn = sf_report_write_plot(f, rep, SF_CANDIDATE_TRANSMITTANCE);
  fclose(f);
  int count = 0;
  for (const char *p = text; drawn && (p = strstr(p, needle)) != NULL; ++p) ++count;
  free(text);
  return drawn ? count : -1;
}

static int index_of(const sf_report *rep, const char *name) {
  for (int i = 0; i < rep->n_models; ++i)
    if (strcmp(rep->models[i].candidate->name, name) == 0) return i;
  return -1;
}

int main(void) {
  sf_scene *scene = calloc(1, sizeof *scene);
  sf_scene_default(scene);
  scene->quantities = SF_QUANTITY_TRANSMITTANCE;
  scene->transmittance_rmse_budget = 1e-3;
  sf_candidate cands[8];
  sf_report rep;

  /* Costs within SF_REPORT_COST_TIE of the cheapest's tie, the smaller
   * error winning; farther apart, the cheaper wins whatever its error. */
  for (int far = 0; far < 2; ++far) {
    const fake tie[] = {{"reference", SF_ROLE_REFERENCE, 0, 1, 0, 0, 0},
                        {"flat", SF_ROLE_BASELINE, 1, 1, 0.253, 6.7e-4, 7e-4},
                        {"chapman", SF_ROLE_BASELINE, 1, 1, far ? 0.253 * 1.11 : 0.253 * 1.09, 2e-4, 2e-4}};
    fill(&rep, cands, tie, 3);
    sf_report_select(&rep, scene);
    const sf_report_selection *s = &rep.selection[SF_CANDIDATE_TRANSMITTANCE];
    printf("costs %s 10 %% apart: selected %s\n  %s\n", far ? "11" : "9",
           s->model >= 0 ? rep.models[s->model].candidate->name : "none", s->reason);
    CHECK(s->model == index_of(&rep, far ? "flat" : "chapman") && s->meets_budget);
    CHECK((strstr(s->reason, "most accurate") != NULL) == !far);
    free(rep.models);
  }

  /* The table is cheaper and better than everything but cannot ship. */
  const fake within[] = {
      {"reference", SF_ROLE_REFERENCE, 0, 1, 0, 0, 0},     {"table", SF_ROLE_LOOKUP, 0, 1, 0.05, 1e-6, 1e-5},
      {"naive16", SF_ROLE_BASELINE, 1, 1, 1.0, 3e-3, 4e-3}, {"chapman", SF_ROLE_BASELINE, 1, 1, 0.3, 2e-2, 2e-2},
      {"mlp", SF_ROLE_FITTED, 1, 1, 1.1, 7e-4, 8e-4},       {"big-mlp", SF_ROLE_FITTED, 1, 1, 2.0, 5e-4, 6e-4},
      {"ground", SF_ROLE_FITTED, 1, 0, 0.1, 1e-5, 1e-5},   {"slow", SF_ROLE_BASELINE, 1, 1, 1.5, 5e-3, 6e-3}};
  fill(&rep, cands, within, 8);
  sf_report_select(&rep, scene);
  const sf_report_selection *sel = &rep.selection[SF_CANDIDATE_TRANSMITTANCE];
  printf("within: selected %s; front:", sel->model >= 0 ? rep.models[sel->model].candidate->name : "none");
  for (int i = 0; i < rep.n_models; ++i)
    if (rep.models[i].on_front) printf(" %s", rep.models[i].candidate->name);
  printf("\n  %s\n", sel->reason);
  CHECK(sel->model == index_of(&rep, "mlp") && sel->meets_budget);
  CHECK(rep.models[index_of(&rep, "mlp")].on_front && rep.models[index_of(&rep, "big-mlp")].on_front &&
        rep.models[index_of(&rep, "chapman")].on_front && rep.models[index_of(&rep, "naive16")].on_front);
  CHECK(!rep.models[index_of(&rep, "table")].on_front && !rep.models[index_of(&rep, "ground")].on_front &&
        !rep.models[index_of(&rep, "slow")].on_front);
  CHECK(strstr(sel->reason, "FAILED") == NULL);
  /* The plot draws the front of four as one green line through them */
  CHECK(plot_front_marks(&rep, "<polyline fill=\"none\" stroke=\"#2a7\"") == 1 &&
        plot_front_marks(&rep, "stroke=\"#2a7\" stroke-width=\"2\"/>") == 0);
  free(rep.models);

  /* A front of one model (it dominates every other that can ship) is
   * marked by a green ring: it had not been marked at all. */
  const fake alone[] = {{"reference", SF_ROLE_REFERENCE, 0, 1, 0, 0, 0},
                        {"naive16", SF_ROLE_BASELINE, 1, 1, 1.0, 3e-3, 4e-3},
                        {"mlp", SF_ROLE_FITTED, 1, 1, 0.5, 7e-4, 8e-4}};
  fill(&rep, cands, alone, 3);
  sf_report_select(&rep, scene);
  CHECK(rep.models[index_of(&rep, "mlp")].on_front && !rep.models[index_of(&rep, "naive16")].on_front);
  CHECK(plot_front_marks(&rep, "<polyline fill=\"none\" stroke=\"#2a7\"") == 0 &&
        plot_front_marks(&rep, "r=\"11\" fill=\"none\" stroke=\"#2a7\"") == 1);
  free(rep.models);

  /* None meets the budget; one fit failed (relative RMSE above 1). */
  const fake missing[] = {{"reference", SF_ROLE_REFERENCE, 0, 1, 0, 0, 0},
                          {"naive16", SF_ROLE_BASELINE, 1, 1, 1.0, 3e-3, 4e-3},
                          {"mlp", SF_ROLE_FITTED, 1, 1, 1.1, 2e-3, 2e-3},
                          {"hosek", SF_ROLE_FITTED, 1, 1, 0.2, 30.0, 300.0}};
  fill(&rep, cands, missing, 4);
  sf_report_select(&rep, scene);
  printf("missing: %s\n", sel->reason);
  CHECK(sel->model == index_of(&rep, "mlp") && !sel->meets_budget);
  CHECK(strstr(sel->reason, "NO MODEL MEETS THE BUDGET") != NULL);
  CHECK(strstr(sel->reason, "hosek FAILED") != NULL && strstr(sel->reason, "mlp FAILED") == NULL);
  free(rep.models);

  /* Not asked for: nothing selected. */
  scene->quantities = SF_QUANTITY_SKY_RADIANCE;
  fill(&rep, cands, within, 8);
  sf_report_select(&rep, scene);
  CHECK(!sel->asked && sel->model < 0);
  free(rep.models);
  free(scene);
  return check_summary();
}
