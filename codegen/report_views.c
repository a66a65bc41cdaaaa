#include "codegen/report_views.h"

#include <dirent.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "data/parallel_rows.h"
#include "data/sky_lookup.h"
#include "models/ciede2000.h"
#include "models/color_space.h"
#include "models/single_scattering.h"
#include "models/views_standard.h"
#include "util/exr_image.h"
#include "util/make_folders.h"
#include "util/png_write.h"

/* Where pixel (i, j)'s ray starts in the atmosphere: {h_km, mu, mu_s} at
 * the viewer, or where a viewer above the top enters (as the reference
 * looks it up, data/sky_lookup.h). A ray that never enters starts nowhere:
 * start[0] is then the viewer's altitude clamped to the top, and the
 * function returns 0. */
static int pixel_start(const sf_view_camera *cam, const sf_atmosphere *atm, int i, int j, double start[3]) {
  double in[4];
  sf_view_pixel_inputs(cam, atm, i, j, in);
  double r, mu = in[1], mu_s = in[2];
  if (!sf_sky_enter_atmosphere(atm, in[0], &r, &mu, &mu_s, sf_clamp_nu(in[1], in[2], in[3]))) {
    start[0] = fmin(in[0], atm->top_radius_km - atm->bottom_radius_km);
    return 0;
  }
  start[0] = r - atm->bottom_radius_km;
  start[1] = mu;
  start[2] = mu_s;
  return 1;
}

/* Does box hold the start (or, for a ray that never enters, the viewer's
 * clamped altitude: a model of the sky from the ground has nothing to say
 * about the black of space seen from orbit)? */
static int box_holds(const sf_scene_domain *b, const double start[3], int entered, int with_sun) {
  const double slack = 1e-6;
  if (start[0] < b->h_min_km - slack || start[0] > b->h_max_km + slack) return 0;
  if (!entered) return 1;
  return start[1] >= b->mu_min - slack && start[1] <= b->mu_max + slack &&
         (!with_sun || (start[2] >= b->mu_s_min - slack && start[2] <= b->mu_s_max + slack));
}

/* mask[p] = 1 where picture data exist for a model valid on box (NULL:
 * everywhere); returns the number of such pixels. */
static size_t pixel_mask(const sf_view_camera *cam, const sf_atmosphere *atm, const sf_scene_domain *box,
                         int with_sun, unsigned char *mask) {
  size_t count = 0;
  for (int j = 0; j < cam->height; ++j)
    for (int i = 0; i < cam->width; ++i) {
      double start[3];
      size_t p = (size_t)j * (size_t)cam->width + (size_t)i;
      mask[p] = !box || box_holds(box, start, pixel_start(cam, atm, i, j, start), with_sun);
      count += mask[p];
    }
  return count;
}

typedef struct render_job {
  const sf_candidate *c;
  const sf_view_camera *cam;
  const sf_atmosphere *atm;
  double scale;     /* exposure x sun irradiance (sky radiance), 1 (transmittance) */
  const unsigned char *mask;
  float *pixels;
} render_job;

static void render_row(void *ctx, int thread, long row) {
  (void)thread;
  const render_job *j = ctx;
  double in[4], out[SF_MAX_CHANNELS];
  for (int i = 0; i < j->cam->width; ++i) {
    size_t p = (size_t)row * (size_t)j->cam->width + (size_t)i;
    float *px = j->pixels + 3 * p;
    if (!j->mask[p]) {
      px[0] = px[1] = px[2] = 0.0f;
      continue;
    }
    sf_view_pixel_inputs(j->cam, j->atm, i, (int)row, in);
    j->c->eval(j->c->ctx, in, out);
    for (int k = 0; k < 3; ++k) px[k] = (float)(j->scale * out[k]);
  }
}

static void render(const sf_candidate *c, const sf_view_camera *cam, const sf_atmosphere *atm, double scale,
                   const unsigned char *mask, float *pixels, const sf_report_options *o) {
  render_job job = {c, cam, atm, scale, mask, pixels};
  sf_precompute_options quiet = {.n_threads = o->run.n_threads};
  sf_parallel_rows(cam->height, &quiet, NULL, render_row, &job);
}

static int write_png(const char *dir, const char *name, const float *pixels, int w, int h, int tonemap,
                     sf_error *err) {
  size_t n = (size_t)w * (size_t)h;
  unsigned char *rgb = malloc(3 * n);
  if (!rgb) return sf_fail(err, SF_ERR_INTERNAL, "out of memory");
  sf_view_to_srgb8(pixels, n, tonemap, rgb);
  char path[SF_REPORT_PATH_LEN + 160];
  snprintf(path, sizeof path, "%s/%s", dir, name);
  int status = sf_png_write_rgb8(path, w, h, rgb, err);
  free(rgb);
  return status;
}

/* RMSE (seed 000 eq. 61) of the exposed linear values and mean ΔE2000 of
 * the colours the PNGs show (tone mapped for sky radiance, as they are for
 * transmittance), over the pixels both pictures hold (both[p]). */
static int compare_view(sf_report_view *v, const float *model, const float *truth, const unsigned char *both,
                        int w, int h, int tonemap, const char *dir, float *scratch, sf_error *err) {
  size_t n = (size_t)w * (size_t)h, compared = 0;
  double sq = 0.0, de = 0.0;
  v->non_finite_pixels = 0;
  for (size_t p = 0; p < n; ++p) {
    if (!both[p]) {
      scratch[3 * p] = scratch[3 * p + 1] = scratch[3 * p + 2] = 0.0f;
      continue;
    }
    double a[3], b[3], la[3], lb[3];
    int finite = 1;
    for (int k = 0; k < 3; ++k) finite &= isfinite(model[3 * p + k]) != 0;
    v->non_finite_pixels += !finite;
    for (int k = 0; k < 3; ++k) {
      double mv = isfinite(model[3 * p + k]) ? model[3 * p + k] : 0.0;
      double e = mv - truth[3 * p + k];
      sq += e * e;
      scratch[3 * p + k] = (float)fabs(e);
      a[k] = tonemap ? mv : fmin(fmax(mv, 0.0), 1.0);   /* what the PNG shows */
      b[k] = tonemap ? truth[3 * p + k] : fmin(fmax(truth[3 * p + k], 0.0), 1.0);
    }
    /* Values are already exposed: exposure 1 here. */
    if (tonemap) {
      sf_display_lab(a, 1.0, la);
      sf_display_lab(b, 1.0, lb);
    } else {
      sf_linear_lab(a, la);
      sf_linear_lab(b, lb);
    }
    de += sf_ciede2000(la, lb);
    ++compared;
  }
  v->compared_fraction = (double)compared / (double)n;
  v->rmse = compared ? sqrt(sq / (3.0 * (double)compared)) : 0.0;
  v->mean_delta_e = compared ? de / (double)compared : 0.0;
  char path[SF_REPORT_PATH_LEN + 160];
  snprintf(path, sizeof path, "%s/%s", dir, v->error_exr);
  static const char *const names[3] = {"R", "G", "B"};
  return sf_exr_write_image(path, w, h, 3, names, scratch, err);
}

static void note_view(sf_report *rep, const char *opening, const char *view) {
  size_t len = strlen(rep->views_note);
  snprintf(rep->views_note + len, sizeof rep->views_note - len, "%s%s", len ? ", " : opening, view);
}

/* A model that gives NaN or infinity somewhere in a view must not pass
 * for a good one there: those pixels count as 0 in its figures, so the
 * note names them. */
static void note_non_finite_pixels(sf_report *rep) {
  int first = 1;
  for (int i = 0; i < rep->n_models; ++i)
    for (int v = 0; v < rep->models[i].n_views; ++v) {
      const sf_report_view *rv = &rep->models[i].views[v];
      if (rv->non_finite_pixels == 0) continue;
      size_t len = strlen(rep->views_note);
      const char *lead = !first ? ", " : len ? ". Not finite, 0 in the figures: " : "Not finite, 0 in the figures: ";
      snprintf(rep->views_note + len, sizeof rep->views_note - len, "%s%s's %s view %s (%zu pixels)", lead,
               rep->models[i].candidate->name, sf_candidate_quantity_name(rep->models[i].candidate->quantity),
               rv->name, rv->non_finite_pixels);
      first = 0;
    }
}

int sf_report_render_views(sf_report *rep, const sf_scene *scene, const sf_report_options *o, sf_error *err) {
  const sf_atmosphere *atm = &scene->atmosphere;
  int w = o->view_width, h = o->view_height;
  size_t n = (size_t)w * (size_t)h;
  char dir[SF_REPORT_PATH_LEN + 16];
  snprintf(dir, sizeof dir, "%s/views", rep->out_dir);
  if (sf_make_folders(dir, "report folder", err) != SF_OK) return err->status;
  float *truth = malloc(sizeof(float) * 3 * n), *model = malloc(sizeof(float) * 3 * n),
        *scratch = malloc(sizeof(float) * 3 * n);
  unsigned char *truth_mask = malloc(n), *model_mask = malloc(n), *both = malloc(n);
  if (!truth || !model || !scratch || !truth_mask || !model_mask || !both) {
    free(truth); free(model); free(scratch); free(truth_mask); free(model_mask); free(both);
    return sf_fail(err, SF_ERR_INTERNAL, "out of memory for %dx%d views", w, h);
  }
  int status = SF_OK;
  for (int q = 0; q < SF_CANDIDATE_N_QUANTITIES && status == SF_OK; ++q) {
    if (rep->reference[q] < 0) continue;
    int sky = q == SF_CANDIDATE_SKY_RADIANCE;
    const sf_view_def *views;
    int nv = sky ? sf_standard_radiance_views(&views) : sf_standard_transmittance_views(&views);
    const char *qname = sf_candidate_quantity_name((sf_candidate_quantity)q);
    for (int vi = 0; vi < nv && status == SF_OK; ++vi) {
      if (o->run.progress)
        o->run.progress(o->run.progress_ctx, sky ? "views (sky radiance)" : "views (transmittance)",
                        (double)vi / nv);
      sf_view_camera cam;
      sf_view_camera_make(&views[vi], atm, w, h, &cam);
      double scale = sky ? views[vi].exposure * SF_VIEW_SUN_IRRADIANCE : 1.0;
      /* The sky-radiance reference (the tables) covers the scene's domain
       * only; the transmittance reference is exact everywhere. */
      size_t truth_pixels = pixel_mask(&cam, atm, sky ? &rep->domain : NULL, 1, truth_mask);
      if (truth_pixels == 0) note_view(rep, "No pixel in the scene's domain, not rendered: ", views[vi].name);
      for (int i = 0; i < rep->n_models && status == SF_OK; ++i) {
        sf_report_model *m = &rep->models[i];
        const sf_candidate *c = m->candidate;
        if ((int)c->quantity != q || m->n_views >= SF_REPORT_MAX_VIEWS) continue;
        sf_report_view *v = &m->views[m->n_views++];
        snprintf(v->name, sizeof v->name, "%s", views[vi].name);
        if (truth_pixels == 0 || c->role != SF_ROLE_REFERENCE) continue;
        v->rendered = 1;
        v->compared_fraction = (double)truth_pixels / (double)n;
        snprintf(v->png, sizeof v->png, "views/%s-%s-%s.png", qname, views[vi].name, c->name);
        render(c, &cam, atm, scale, truth_mask, truth, o);
        status = write_png(rep->out_dir, v->png, truth, w, h, sky, err);
      }
      /* Now that the reference picture exists: every other model once. */
      for (int i = 0; i < rep->n_models && status == SF_OK && truth_pixels > 0; ++i) {
        sf_report_model *m = &rep->models[i];
        const sf_candidate *c = m->candidate;
        if ((int)c->quantity != q || c->role == SF_ROLE_REFERENCE || m->n_views == 0) continue;
        sf_report_view *v = &m->views[m->n_views - 1];
        /* Sun-dependent validity only matters for sky radiance. */
        pixel_mask(&cam, atm, &c->valid, sky, model_mask);
        size_t shared = 0;
        for (size_t p = 0; p < n; ++p) shared += both[p] = truth_mask[p] && model_mask[p];
        if (shared == 0) continue;
        v->rendered = 1;
        snprintf(v->png, sizeof v->png, "views/%s-%s-%s.png", qname, views[vi].name, c->name);
        render(c, &cam, atm, scale, model_mask, model, o);
        status = write_png(rep->out_dir, v->png, model, w, h, sky, err);
        if (status != SF_OK) break;
        snprintf(v->error_exr, sizeof v->error_exr, "views/%s-%s-%s-error.exr", qname, views[vi].name, c->name);
        status = compare_view(v, model, truth, both, w, h, sky, rep->out_dir, scratch, err);
      }
    }
  }
  free(truth); free(model); free(scratch); free(truth_mask); free(model_mask); free(both);
  note_non_finite_pixels(rep);
  int partial = 0;
  for (int i = 0; i < rep->n_models; ++i)
    for (int v = 0; v < rep->models[i].n_views; ++v)
      partial |= rep->models[i].views[v].rendered && rep->models[i].views[v].compared_fraction < SF_REPORT_VIEW_WHOLE;
  if (partial) {
    size_t len = strlen(rep->views_note);
    snprintf(rep->views_note + len, sizeof rep->views_note - len,
             "%sA figure marked [N %%] is over that share of the view's pixels: the others lie outside the "
             "model's valid domain or, for sky radiance, the scene's (where the reference tables have no "
             "data); they are black in that picture and 0 in its error map.",
             len ? ". " : "");
  }
  return status;
}

static int ends_with(const char *s, const char *end) {
  size_t n = strlen(s), m = strlen(end);
  return n >= m && strcmp(s + n - m, end) == 0;
}

static int named_by(const sf_report *rep, const char *file) {
  for (int i = 0; i < rep->n_models; ++i)
    for (int v = 0; v < rep->models[i].n_views; ++v) {
      const sf_report_view *rv = &rep->models[i].views[v];
      if (!rv->rendered) continue;
      if (strcmp(rv->png + strlen("views/"), file) == 0) return 1;
      if (rv->error_exr[0] && strcmp(rv->error_exr + strlen("views/"), file) == 0) return 1;
    }
  return 0;
}

int sf_report_remove_stale_pictures(const sf_report *rep, const char *out_dir, int *n_removed, sf_error *err) {
  *n_removed = 0;
  char dir[SF_REPORT_PATH_LEN + 16];
  snprintf(dir, sizeof dir, "%s/views", out_dir);
  DIR *d = opendir(dir);
  int status = SF_OK;
  for (struct dirent *e; d && (e = readdir(d)) != NULL;) {
    const char *name = e->d_name;
    int ours = (strncmp(name, "transmittance-", 14) == 0 || strncmp(name, "sky_radiance-", 13) == 0) &&
               (ends_with(name, ".png") || ends_with(name, ".exr"));
    if (!ours || named_by(rep, name)) continue;
    char path[SF_REPORT_PATH_LEN + 300];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    if (unlink(path) == 0) ++*n_removed;
    else if (status == SF_OK) status = sf_fail(err, SF_ERR_INTERNAL, "%s: cannot remove: %s", path, strerror(errno));
  }
  if (d) closedir(d);
  for (int q = 0; q < SF_CANDIDATE_N_QUANTITIES; ++q) {
    if (sf_report_plot_has_points(rep, q)) continue;
    char path[SF_REPORT_PATH_LEN + 64];
    snprintf(path, sizeof path, "%s/plots/%s-cost-error.svg", out_dir,
             sf_candidate_quantity_name((sf_candidate_quantity)q));
    if (unlink(path) == 0) ++*n_removed;
    else if (errno != ENOENT && status == SF_OK)
      status = sf_fail(err, SF_ERR_INTERNAL, "%s: cannot remove: %s", path, strerror(errno));
  }
  return status;
}
