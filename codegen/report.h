/* The fit-quality report (SPEC §12): what was measured for every candidate
 * (fit/candidate.h) of a scene, the selection per quantity, and the writers
 * of report.html (self-contained, inline SVG, PNG previews beside it),
 * report.md and metrics.json, plus the views' PNG previews and EXR error
 * maps (written by sf_report_evaluate).
 *
 * Measuring (sf_report_evaluate), per quantity the scene asks for:
 *  - the reference's values on `domain_samples` seeded in-domain samples
 *    (fit/candidate_metrics.h), and each candidate's errors against them
 *    (a candidate valid on part of the domain only: on as many samples of
 *    that part);
 *  - each candidate's cost on `timing_points` in-domain inputs, median of
 *    `timing_repetitions`, and its ratio to the naive 16-step raymarch timed
 *    in the same run at the same precision (float32 or double);
 *  - the standard views (models/views_standard.h; RGB atmospheres only):
 *    sky radiance on the 12 views of seed 000 App. A/B at their exposures
 *    with the sun at SF_VIEW_SUN_IRRADIANCE x the atmosphere's, and
 *    transmittance on the 5 views of App. C/D; per view and model, over
 *    the pixels where both pictures hold data (codegen/report_views.h),
 *    the RMSE of the exposed linear values (seed 000 eq. 61, every
 *    channel), the mean ΔE2000 of the colours the PNGs show (sky: exposure
 *    and tone map 1 - exp(-x); transmittance: as is; CIELAB:
 *    models/color_space.h, models/ciede2000.h), a PNG and an EXR map of
 *    |model - reference| per channel;
 *  - the segment errors of the models that have a segment function
 *    (sf_candidate eval_segment: seed 000 eq. 43, 44), the part of a ray a
 *    renderer's aerial perspective asks for: on `domain_samples` seeded
 *    segments of in-domain rays (fit/segment_samples.h: the end uniform
 *    along the ray's stretch in the air) against the reference's segment
 *    (transmittance: exp(-extinction x the exact optical depth of the
 *    segment); sky radiance: eq. 44 from the tables, L(viewer) - T(viewer
 *    -> end) L(end)), in double as the whole rays are measured
 *    (codegen/report_segments.c). They do not enter the selection, and
 *    are measured after it (sf_report_evaluate selects too): a sky
 *    network's segment takes the transmittance network the header emits
 *    beside it (sf_report_transmittance_partner). Where a selected
 *    model's is far worse than its whole rays', the report says so
 *    (sf_report_segment_note).
 * Selecting (sf_report_select): per quantity, among the candidates that may
 * ship (baselines and fitted models) and that are valid over the whole
 * domain, the cheapest (median ns) whose budget metric — transmittance:
 * RMSE; sky radiance: relative RMSE — meets the scene's budget (costs
 * within SF_REPORT_COST_TIE of it tie, the smaller error winning); if none
 * does, the one with the smallest error, flagged as not meeting it. */
#ifndef SKYFIT_CODEGEN_REPORT_H
#define SKYFIT_CODEGEN_REPORT_H

#include <stddef.h>
#include <stdio.h>

#include "data/precompute_options.h"
#include "data/sky_table_check.h"
#include "fit/candidate.h"
#include "fit/candidate_metrics.h"
#include "models/scene_file.h"
#include "util/error.h"

#define SF_REPORT_MAX_VIEWS 12
/* A view compared on at least this share of its pixels counts as whole:
 * the writers give the share of the others. */
#define SF_REPORT_VIEW_WHOLE 0.9995
#define SF_REPORT_PATH_LEN 4096
/* Candidates within this fraction of the cheapest's cost tie; the smaller
 * error wins (codegen/report_select.c). */
#define SF_REPORT_COST_TIE 0.10

typedef struct sf_report_view {
  char name[32];
  int rendered;              /* 0: no pixel of the view is compared (codegen/report_views.h) */
  double compared_fraction;  /* share of the view's pixels compared: both pictures hold data */
  double rmse, mean_delta_e; /* over those pixels */
  size_t non_finite_pixels;  /* compared pixels with a NaN or infinite channel: such a
                                channel is 0 in the figures and the picture, and the note
                                names the view */
  char png[128], error_exr[128];   /* file names in the report folder */
} sf_report_view;

typedef struct sf_report_model {
  const sf_candidate *candidate;   /* borrowed */
  int has_errors;
  sf_error_metrics errors;
  size_t non_finite;
  int valid_over_domain;           /* the candidate's valid box contains the scene's */
  /* A candidate valid on part of the domain only (Hosek: ground, sun up)
   * is measured on that part (errors_domain = its valid box within the
   * scene's), so its figures say how good it is where it applies. */
  int errors_over_valid_part;
  sf_scene_domain errors_domain;
  /* Its segment function's errors (above); has_segment_errors 0: it has
   * none, or no segment was measured. Over errors_domain, as the whole
   * rays. segment_partner: the transmittance model a sky model's segment
   * took (eq. 44), or NULL. */
  int has_segment_errors;
  sf_error_metrics segment_errors;
  size_t segment_non_finite;
  const sf_candidate *segment_partner;
  int has_cost;
  sf_cost cost;
  double cost_ratio_naive16;       /* ns / naive16's ns at the same precision */
  int n_views;
  sf_report_view views[SF_REPORT_MAX_VIEWS];
  double budget_metric;            /* RMSE or relative RMSE, per quantity */
  int meets_budget, selectable, selected;
  int on_front;                    /* on the Pareto front of cost and error among the models that can ship */
} sf_report_model;

typedef struct sf_report_selection {
  int asked;                       /* the scene asks for this quantity */
  int model;                       /* index into models, -1 none */
  int meets_budget;
  double budget;
  const char *metric;              /* "rmse" or "rel_rmse" */
  char reason[1536];
  char emitted_c[SF_REPORT_PATH_LEN], emitted_glsl[SF_REPORT_PATH_LEN];
  char emit_note[512];             /* what was not emitted and why, if so */
} sf_report_selection;

typedef struct sf_report_options {
  size_t domain_samples;           /* default 20000 */
  size_t timing_points;            /* default 1000000 (SPEC §12) */
  int timing_repetitions;          /* default 3 */
  int view_width, view_height;     /* default 192 x 108 */
  int render_views;                /* default 1 */
  unsigned long long seed;         /* default 1 */
  const char *cost_cache_dir;      /* timings cached here (fit/candidate_cache.h); NULL: always time */
  sf_precompute_options run;       /* threads and progress */
} sf_report_options;

void sf_report_options_default(sf_report_options *o);

/* The 4-wavelength colour model of a spectral4 scene (SPEC §7.3, seed 003
 * §5.4; fit/spectral4_run.h): what the build fitted and its colour error
 * against the full spectrum, next to plain RGB at 680/550/440 nm and 4
 * uniform wavelengths. Filled by fit/build_pipeline_spectral4.h. */
#define SF_REPORT_COLOR_METHODS 3
typedef struct sf_report_spectral4 {
  int present;
  int from_cache;
  char weights_path[SF_REPORT_PATH_LEN];
  double lambda_nm[4], weight_nm[4];
  double loss, rgb_loss, uniform_loss;       /* eq. 5.13 on the training samples */
  int has_aerosols;
  char method[SF_REPORT_COLOR_METHODS][32];  /* "spectral4", "rgb_680_550_440", "uniform4" */
  /* [0] without aerosols (the fit's own atmosphere), [1] with them */
  double mean_de[2][SF_REPORT_COLOR_METHODS], p99_de[2][SF_REPORT_COLOR_METHODS],
      max_de[2][SF_REPORT_COLOR_METHODS];
  double samples[2][SF_REPORT_COLOR_METHODS];
} sf_report_spectral4;

typedef struct sf_report {
  char scene_name[96];
  char atmosphere_name[96];
  char atmosphere_hash[17];
  sf_scene_domain domain;
  unsigned quantities;             /* SF_QUANTITY_* of the scene */
  int n_channels;
  sf_report_options options;
  char out_dir[SF_REPORT_PATH_LEN];
  int n_models;
  sf_report_model *models;
  int reference[SF_CANDIDATE_N_QUANTITIES];   /* index of each quantity's reference, -1 */
  double naive16_ns_f32, naive16_ns_f64;      /* the cost unit, timed in the same run as the others */
  sf_report_selection selection[SF_CANDIDATE_N_QUANTITIES];
  int views_rendered;
  char views_note[1024];
  double seconds_total;                       /* filled by the caller (build) */
  sf_report_spectral4 spectral4;              /* filled by the caller (build) */
  sf_sky_table_check reference_check;         /* filled by the caller (build): the
                                                 sky tables' single scattering against
                                                 direct integration */
  char notes[4096];                           /* models not fitted or skipped, and why; one per line */
} sf_report;

/* Measures every candidate of list (which must hold the reference of each
 * quantity the scene asks for, role SF_ROLE_REFERENCE), makes the
 * selection (sf_report_select; before the segments, above) and writes the
 * view images into out_dir. The report borrows the candidates. */
int sf_report_evaluate(sf_report *rep, const sf_scene *scene, const sf_candidate_list *list,
                       const sf_report_options *opt, const char *out_dir, sf_error *err);
void sf_report_free(sf_report *rep);

/* Fills rep->selection (and each model's meets_budget / selectable /
 * selected / on_front: the front is of the models that can ship); the
 * same again on the same figures. */
void sf_report_select(sf_report *rep, const sf_scene *scene);

/* Where near-zero references make most of m's mean relative error (over
 * SF_METRICS_FLOOR_SHARE_NOTE of it: fit/candidate_metrics.h), that in
 * words (one sentence, plain text, no newline), for report.md and
 * report.html; "" otherwise. */
void sf_report_mean_rel_note(const sf_report_model *m, char *buf, size_t n);

/* A selected model's segment budget metric (transmittance: RMSE; sky
 * radiance: relative RMSE) over this many times its whole rays' is far
 * worse, and the report says so. */
#define SF_REPORT_SEGMENT_NOTE_RATIO 3.0

/* Measures the segment errors of quantity q's models (above) for an
 * atmosphere of the given radii; called by sf_report_evaluate after the
 * selection (codegen/report_segments.c). */
int sf_report_measure_segments(sf_report *rep, const sf_candidate_list *list, sf_candidate_quantity q,
                               double bottom_radius_km, double top_radius_km, const sf_report_options *opt,
                               sf_error *err);

/* What the segment columns are (one sentence, plain text, no newline),
 * for quantity q's table in report.md and report.html; "" when no model of
 * q has segment errors. */
void sf_report_segment_text(const sf_report *rep, int q, char *buf, size_t n);
/* The transmittance network a build emits beside a sky network whose
 * segment (eq. 44) takes networks of emit name emit_name ("mlp"), and the
 * one the report's sky segments take: the selected transmittance model
 * when it is a fitted, emittable model of that name (a restart outside
 * SF_REPORT_COST_TIE of the most accurate's cost may be it); otherwise
 * (another model selected, or no selection yet) the fitted, emittable one
 * of that name with the smallest whole-ray RMSE (one with errors before
 * one without; restarts included), which fit/build_pipeline.c emits
 * beside the selection for the segments; -1 none. */
int sf_report_transmittance_partner(const sf_report *rep, const char *emit_name);
/* Where quantity q's selected model's segments are far worse than its
 * whole rays (SF_REPORT_SEGMENT_NOTE_RATIO), that in words (one sentence,
 * plain text, no newline); "" otherwise. */
void sf_report_segment_note(const sf_report *rep, int q, char *buf, size_t n);

/* The reference check in words (one paragraph, plain text, no newline),
 * for report.md and report.html; "" when it is not present. */
void sf_report_reference_check_text(const sf_report *rep, char *buf, size_t n);

/* out_dir/metrics.json, report.md, report.html (atomically). */
int sf_report_write_json(const sf_report *rep, const char *path, sf_error *err);
int sf_report_write_markdown(const sf_report *rep, const char *path, sf_error *err);
int sf_report_write_html(const sf_report *rep, const char *path, sf_error *err);
int sf_report_write_all(const sf_report *rep, sf_error *err);
/* The speed-against-error plot of quantity q as one <svg> element
 * (codegen/report_plot.c); 0 and nothing written when no model has both a
 * cost and an error. */
int sf_report_write_plot(FILE *f, const sf_report *rep, int q);
/* Whether quantity q's plot has a point (the report measured it, and a
 * model has both a cost and an error). */
int sf_report_plot_has_points(const sf_report *rep, int q);
/* The same as a standalone SVG file at path (*written 0: none to draw,
 * nothing written). */
int sf_report_write_plot_file(const sf_report *rep, int q, const char *path, int *written, sf_error *err);

/* seed 000 App. B (sky-radiance views) and App. D (transmittance views),
 * typed from the paper. Rows follow sf_standard_radiance_views /
 * sf_standard_transmittance_views; values[row * n_columns + column] as
 * printed.
 *
 * The printed figures are mean squared errors, though the appendices head
 * them "RMSE" (eq. 61 has the root). App. B's "Naive" column (a raymarch
 * of single scattering only) is 1.2-5.8x the mean square of the multiple
 * scattering in our reference views (11 of 12 views); as roots its figures
 * would be 9-64x below the multiple scattering's RMS, an error no model
 * without multiple scattering can have. Its "Empty" column (a white image,
 * seed 000 §11.2.1) is within 1.7 % of the mean of (1 - L)^2 over our views
 * in 11 of 12, of its root in 5, the dim views where both are near 1
 * (bench/bench_views_scale.c prints both);
 * the views' camera pitches are chosen to reproduce it (models/
 * views_standard.h), but no pitch brings the roots to it at ground-noon (a
 * white image's MSE would have to be 0.67; it is 0.71 at best).
 * App. D comes from the same procedure (seed 000 §11.5: "This process is
 * repeated for the transmittance models").
 * sf_paper_rmse gives their square roots, which compare with our RMSE. */
typedef struct sf_paper_table {
  int n_columns, n_rows;
  const char *const *columns;
  const char *const *rows;
  const double *values;            /* n_rows * n_columns, as printed (mean squared errors) */
} sf_paper_table;
void sf_paper_appendix_b(sf_paper_table *t);
void sf_paper_appendix_d(sf_paper_table *t);
/* The row of the view named view_name, or -1. */
int sf_paper_row(const sf_paper_table *t, const char *view_name);
/* The column named column_name, or -1. */
int sf_paper_column(const sf_paper_table *t, const char *column_name);
/* The RMSE of the paper's figure at (row, column): its square root; NAN
 * when row or column is -1. */
double sf_paper_rmse(const sf_paper_table *t, int row, int column);

/* The Pareto front of (cost, error) points: on_front[i] = 1 when no other
 * point is at most as costly and at most as wrong with one strictly less. */
void sf_pareto_front(int n, const double *cost, const double *error, int *on_front);

#endif
