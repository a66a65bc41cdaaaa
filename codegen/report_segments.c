/* The report's segment errors (codegen/report.h): each model's segment
 * function against the reference's segment on seeded segments of in-domain
 * rays (fit/segment_samples.h), and what the report says of them. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "codegen/report.h"
#include "fit/segment_samples.h"

/* A segment function as a candidate's eval, so that sf_candidate_values
 * computes it (threads, deterministic): its own ctx, or a sky model's
 * with its transmittance partner's (eq. 44). */
typedef struct paired {
  const sf_candidate *model, *transmittance;
} paired;

static void paired_eval(const void *ctx, const double *in, double *out) {
  const paired *p = ctx;
  p->model->eval_segment_paired(p->model->ctx, p->transmittance->ctx, in, out);
}

/* A fitted transmittance model of emit name emit_name that can be emitted. */
static int is_network(const sf_candidate *c, const char *emit_name) {
  return c->quantity == SF_CANDIDATE_TRANSMITTANCE && c->role == SF_ROLE_FITTED && c->emit && c->emit_model &&
         strcmp(c->emit_name, emit_name) == 0;
}

int sf_report_transmittance_partner(const sf_report *rep, const char *emit_name) {
  /* the selected model when it is such a network: the header emits it,
   * and the sky network's segment calls it (fit/build_pipeline.c) */
  const sf_report_selection *s = &rep->selection[SF_CANDIDATE_TRANSMITTANCE];
  if (s->asked && s->model >= 0 && is_network(rep->models[s->model].candidate, emit_name)) return s->model;
  int best = -1;
  for (int k = 0; k < rep->n_models; ++k) {
    const sf_report_model *m = &rep->models[k];
    if (!is_network(m->candidate, emit_name)) continue;
    const sf_report_model *b = best >= 0 ? &rep->models[best] : NULL;
    if (!b || (m->has_errors && (!b->has_errors || m->errors.rmse < b->errors.rmse))) best = k;
  }
  return best;
}

/* The transmittance candidate a sky model's segment takes, or NULL. */
static const sf_candidate *partner_of(const sf_report *rep, const sf_candidate *c) {
  int k = sf_report_transmittance_partner(rep, c->segment_transmittance);
  return k >= 0 ? rep->models[k].candidate : NULL;
}

/* The segment function of m as a candidate (*as, with *pair its ctx where
 * paired); 0 when m has none. */
static int segment_candidate(const sf_report *rep, sf_report_model *m, sf_candidate *as, paired *pair) {
  const sf_candidate *c = m->candidate;
  *as = *c;   /* as a segment: none of the whole ray's float32 port, ownership or segments */
  as->eval_f32 = NULL;
  as->free_ctx = NULL;
  as->eval_segment = NULL;
  as->eval_segment_paired = NULL;
  if (c->eval_segment_paired) {
    const sf_candidate *t = partner_of(rep, c);
    if (!t) return 0;
    pair->model = c;
    pair->transmittance = t;
    m->segment_partner = t;
    as->eval = paired_eval;
    as->ctx = pair;
    return 1;
  }
  if (!c->eval_segment) return 0;
  as->eval = c->eval_segment;
  return 1;
}

/* The segment errors of the models of quantity q measured on box d: those
 * with whole-ray errors over d (only < 0: every such model over the
 * domain; else model only, on its valid part). */
static int segments_on(sf_report *rep, const sf_candidate_list *list, sf_candidate_quantity q,
                       const sf_scene_domain *d, int only, double bottom, double top, const sf_report_options *o,
                       sf_error *err) {
  const sf_candidate *ref = &list->items[rep->reference[q]];
  sf_candidate ref_as;
  paired unused;
  sf_report_model ref_model = {0};
  ref_model.candidate = ref;
  if (!segment_candidate(rep, &ref_model, &ref_as, &unused)) return SF_OK;   /* no reference to measure against */
  int any = 0;
  for (int i = 0; i < rep->n_models && !any; ++i) {
    const sf_report_model *m = &rep->models[i];
    const sf_candidate *c = m->candidate;
    any = c->quantity == q && c->role != SF_ROLE_REFERENCE && (only >= 0 ? i == only : !m->errors_over_valid_part) &&
          (c->eval_segment || c->eval_segment_paired);
  }
  if (!any) return SF_OK;
  sf_domain_samples s;
  if (sf_segment_samples_make(d, bottom, top, q, o->domain_samples, o->seed, &s, err) != SF_OK) return err->status;
  if (s.n == 0) {   /* every ray misses the atmosphere */
    sf_domain_samples_free(&s);
    return SF_OK;
  }
  size_t nv = s.n * (size_t)ref->n_channels;
  double *truth = malloc(sizeof(double) * nv), *model = malloc(sizeof(double) * nv);
  if (!truth || !model) {
    free(truth); free(model); sf_domain_samples_free(&s);
    return sf_fail(err, SF_ERR_INTERNAL, "out of memory");
  }
  sf_candidate_values(&ref_as, &s, truth, &o->run);
  for (int i = 0; i < rep->n_models; ++i) {
    sf_report_model *m = &rep->models[i];
    const sf_candidate *c = m->candidate;
    if (c->quantity != q || c->role == SF_ROLE_REFERENCE || c->n_channels != ref->n_channels) continue;
    if (only >= 0 ? i != only : m->errors_over_valid_part) continue;
    sf_candidate as;
    paired pair;
    if (!segment_candidate(rep, m, &as, &pair)) continue;
    sf_candidate_values(&as, &s, model, &o->run);
    sf_error_metrics_compute(model, truth, nv, &m->segment_errors, &m->segment_non_finite);
    m->has_segment_errors = 1;
  }
  free(truth); free(model);
  sf_domain_samples_free(&s);
  return SF_OK;
}

int sf_report_measure_segments(sf_report *rep, const sf_candidate_list *list, sf_candidate_quantity q,
                               double bottom_radius_km, double top_radius_km, const sf_report_options *opt,
                               sf_error *err) {
  if (rep->reference[q] < 0) return SF_OK;
  if (segments_on(rep, list, q, &rep->domain, -1, bottom_radius_km, top_radius_km, opt, err) != SF_OK)
    return err->status;
  for (int i = 0; i < rep->n_models; ++i) {
    const sf_report_model *m = &rep->models[i];
    if (m->candidate->quantity != q || !m->errors_over_valid_part) continue;
    sf_scene_domain part = m->errors_domain;
    if (segments_on(rep, list, q, &part, i, bottom_radius_km, top_radius_km, opt, err) != SF_OK) return err->status;
  }
  return SF_OK;
}

void sf_report_segment_text(const sf_report *rep, int q, char *buf, size_t n) {
  buf[0] = '\0';
  size_t samples = 0;
  const char *partner = NULL;
  for (int i = 0; i < rep->n_models; ++i) {
    const sf_report_model *m = &rep->models[i];
    if ((int)m->candidate->quantity != q || !m->has_segment_errors) continue;
    if (!samples && rep->n_channels > 0 && !m->errors_over_valid_part)   /* over the whole domain */
      samples = (m->segment_errors.n_values + m->segment_non_finite) / (size_t)rep->n_channels;
    if (m->segment_partner && !partner) partner = m->segment_partner->name;
  }
  if (!samples) return;
  if (q == SF_CANDIDATE_TRANSMITTANCE)
    snprintf(buf, n,
             "seg RMSE, seg max, seg rel RMSE: the model's segment function (skyfit_<model>_transmittance_segment, seed 000 eq. 43), "
             "the ray from the viewer to a distance uniform along its stretch in the air, on %zu seeded "
             "in-domain rays, against exp(-extinction x the exact optical depth of the segment), in double as the "
             "whole rays; renderers use it for aerial perspective. It does not enter the selection; - : the model "
             "has no segment function.",
             samples);
  else
    snprintf(buf, n,
             "seg RMSE, seg max, seg rel RMSE: the model's segment function (skyfit_<model>_sky_radiance_segment, seed 000 eq. 44%s%s), "
             "the ray from the viewer to a distance uniform along its stretch in the air, on %zu seeded "
             "in-domain rays, against eq. 44 from the tables, L(viewer) - T(segment) L(end), T from the exact "
             "optical depth; renderers use it for aerial perspective. It does not enter the selection; - : the "
             "model has no segment function (whole rays only).",
             partner ? ", with the transmittance of " : "", partner ? partner : "", samples);
}

void sf_report_segment_note(const sf_report *rep, int q, char *buf, size_t n) {
  buf[0] = '\0';
  const sf_report_selection *s = &rep->selection[q];
  if (!s->asked || s->model < 0) return;
  const sf_report_model *m = &rep->models[s->model];
  if (!m->has_errors || !m->has_segment_errors) return;
  int rel = q == SF_CANDIDATE_SKY_RADIANCE;
  double whole = rel ? m->errors.rel_rmse : m->errors.rmse;
  double seg = rel ? m->segment_errors.rel_rmse : m->segment_errors.rmse;
  if (!(seg > SF_REPORT_SEGMENT_NOTE_RATIO * whole)) return;
  snprintf(buf, n,
           "The selected %s's segments are far worse than its whole rays: %s %.3g on segments against %.3g on whole "
           "rays (%.1fx; max abs %.3g against %.3g); the selection weighs whole rays only, and a renderer's aerial "
           "perspective uses the segments.",
           m->candidate->name, rel ? "relative RMSE" : "RMSE", seg, whole, whole > 0.0 ? seg / whole : INFINITY,
           m->segment_errors.max_abs, m->errors.max_abs);
}
