/* How our per-view sky-radiance RMSE (the report's App. B table,
 * fit/mlp_sky_metrics.h) compares in scale with seed 000 App. B, and where a
 * scattering network's error lies. Per standard view (models/views_standard.h,
 * 192 x 108, exposure x sun irradiance 6 as the report renders):
 *   - the reference's RMS, and the share of pixels whose ray meets the
 *     atmosphere where the sun is below the domain's lowest (there the
 *     tables hold their edge's values: the view is only partly a test);
 *   - the evidence that App. B's figures are mean squared errors, not the
 *     RMSE their heading says (codegen/report.h):
 *       the mean of (1 - L)^2, a white image's squared error (1 in every
 *       channel), beside App. B's "Empty" column (seed 000 §11.2.1: the
 *       empty shader "only outputs a white image"), and the root of it;
 *       the mean squared multiple scattering of the view (the error of
 *       single scattering alone), beside App. B's "Naive" column (a
 *       raymarch of single scattering, seed 000 §11.2.6): as a mean square
 *       the seed's naive model errs by somewhat more than that, as a root
 *       it would err by 9-64x less, which no model without multiple
 *       scattering can;
 *   - the network's RMSE over every pixel (the report's figure), then split
 *     into pixels whose ray leaves the atmosphere (sky) and pixels whose ray
 *     ends on the ground (from a ground viewer those rays have length 0 and
 *     the reference is exactly 0; viewers in space enter at the top first);
 *   - App. B's Neural Net figure as an RMSE (its square root), our network's
 *     error relative to our reference's RMS, and our error over the seed's
 *     (below 1: ours is lower, the target).
 *   bench_views_scale OUT [W.json]
 * OUT: the folder of a `skyfit build` of the built-in scene (its table cache
 * OUT/cache is read, and OUT/weights/mlp-scattering.json unless W.json, a
 * scattering network trained elsewhere, is given). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "bench/build_tables.h"
#include "codegen/report.h"
#include "data/sky_lookup.h"
#include "data/table_set.h"
#include "models/mlp_sky.h"
#include "models/ray_geometry.h"
#include "models/scene_file.h"
#include "models/views_standard.h"

typedef struct pixel_sums {
  double ref_sq, white_sq, multiple_sq, err_sq;
  long values;
} pixel_sums;

/* Whether the ray of a pixel (inputs in) meets the atmosphere where the sun
 * is below the domain's lowest: there the tables, our reference, hold their
 * edge's values and the network extrapolates. */
static int sun_below_domain(const sf_atmosphere *atm, const double in[4], double mu_s_min) {
  double r, mu = in[1], mu_s = in[2];
  return sf_sky_enter_atmosphere(atm, in[0], &r, &mu, &mu_s, in[3]) && mu_s < mu_s_min - 1e-9;
}

static double rms(double sum_sq, long n) { return n > 0 ? sqrt(sum_sq / (double)n) : 0.0; }

int main(int argc, char **argv) {
  if (argc != 2 && argc != 3) {
    fprintf(stderr, "usage: bench_views_scale OUT [W.json]   (OUT: a `skyfit build` of the built-in scene)\n");
    return 2;
  }
  sf_error err = {0};
  sf_scene_domain domain;
  sf_scene *scene = bench_default_scene(&domain, &err);
  if (!scene) {
    fprintf(stderr, "%s\n", err.message);
    return 1;
  }
  char weights[4096];
  if (argc == 3)
    snprintf(weights, sizeof weights, "%s", argv[2]);
  else
    snprintf(weights, sizeof weights, "%s/weights/mlp-scattering.json", argv[1]);
  /* and over every sun: the reference where the views' rays meet the
   * atmosphere with the sun below the domain's lowest */
  sf_scene_domain every_sun = domain;
  every_sun.mu_s_min = -1.0;
  every_sun.mu_s_max = 1.0;
  sf_table_set set, set_wide;
  sf_mlp_sky net;
  if (bench_build_tables(argv[1], scene, &domain, &set, &err) ||
      bench_build_tables(argv[1], scene, &every_sun, &set_wide, &err) || sf_mlp_sky_load(weights, &net, &err)) {
    fprintf(stderr, "%s\n", err.message);
    return 1;
  }
  int cached = 0;
  for (int t = 0; t < set.n_tables; ++t) cached += set.from_cache[t];
  sf_sky_tables sky, sky_wide;
  sf_sky_tables_of_set(&sky, &scene->atmosphere, &set);
  sf_sky_tables_of_set(&sky_wide, &scene->atmosphere, &set_wide);
  double wide_tables_sq[16] = {0}, wide_net_sq[16] = {0}, wide_outside[16] = {0};
  sf_paper_table paper;
  sf_paper_appendix_b(&paper);
  const sf_atmosphere *atm = &scene->atmosphere;
  const sf_view_def *views;
  int nv = sf_standard_radiance_views(&views);
  const int W = SF_VIEW_DEFAULT_WIDTH, H = SF_VIEW_DEFAULT_HEIGHT;
  printf("tables: %d of %d from %s/cache; network %s\n", cached, set.n_tables, argv[1], weights);
  printf("%-21s | %8s %6s | %9s %9s %6s | %9s %9s | %9s %9s %9s | %9s | %7s %7s\n", "view", "ref RMS", "out %",
         "white MSE", "seed Empty", "root", "multi MSE", "seed Naive", "net all", "net sky", "net ground", "seed NN",
         "net/RMS", "/seed NN");
  for (int v = 0; v < nv; ++v) {
    sf_view_camera cam;
    sf_view_camera_make(&views[v], atm, W, H, &cam);
    double scale = views[v].exposure * SF_VIEW_SUN_IRRADIANCE;
    pixel_sums part[2] = {{0}};   /* [0] sky, [1] ground */
    long outside = 0;
    for (int j = 0; j < H; ++j)
      for (int i = 0; i < W; ++i) {
        double in[4], L[SF_MAX_CHANNELS];
        sf_view_pixel_inputs(&cam, atm, i, j, in);
        outside += sun_below_domain(atm, in, domain.mu_s_min);
        sf_sky_sample ref, ref_wide;
        sf_sky_lookup(&sky, in[0], in[1], in[2], in[3], &ref);
        sf_sky_lookup(&sky_wide, in[0], in[1], in[2], in[3], &ref_wide);
        sf_mlp_scattering(&net, in[0], in[1], in[2], in[3], L);
        for (int c = 0; v < 16 && c < atm->n_channels; ++c) {
          double w = ref_wide.radiance[c] * scale;
          wide_tables_sq[v] += (ref.radiance[c] * scale - w) * (ref.radiance[c] * scale - w);
          wide_net_sq[v] += (L[c] * scale - w) * (L[c] * scale - w);
        }
        double r = atm->bottom_radius_km + in[0];
        int ground = sf_ray_hits_sphere_from_above(r, in[1], atm->bottom_radius_km);
        for (int c = 0; c < atm->n_channels; ++c) {
          double a = ref.radiance[c] * scale, b = L[c] * scale;
          part[ground].ref_sq += a * a;
          part[ground].white_sq += (1.0 - a) * (1.0 - a);
          part[ground].multiple_sq += ref.multiple[c] * scale * ref.multiple[c] * scale;
          part[ground].err_sq += (a - b) * (a - b);
          part[ground].values++;
        }
      }
    long n = part[0].values + part[1].values;
    double ref_rms = rms(part[0].ref_sq + part[1].ref_sq, n), net_all = rms(part[0].err_sq + part[1].err_sq, n);
    double white_mse = (part[0].white_sq + part[1].white_sq) / (double)n;
    int row = sf_paper_row(&paper, views[v].name);
    double empty = paper.values[row * paper.n_columns + sf_paper_column(&paper, "Empty")];
    double naive = paper.values[row * paper.n_columns + sf_paper_column(&paper, "Naive")];
    double nn = sf_paper_rmse(&paper, row, sf_paper_column(&paper, "Neural Net"));
    printf("%-21s | %8.3g %6.1f | %9.3g %9.3g %6.3g | %9.3g %9.3g | %9.3g %9.3g %9.3g | %9.3g | %7.3g %7.3g\n",
           views[v].name, ref_rms, 100.0 * (double)outside / ((double)W * H), white_mse, empty, sqrt(white_mse),
           (part[0].multiple_sq + part[1].multiple_sq) / (double)n, naive, net_all,
           rms(part[0].err_sq, part[0].values), rms(part[1].err_sq, part[1].values), nn,
           ref_rms > 0 ? net_all / ref_rms : NAN, net_all / nn);
    if (v < 16) wide_outside[v] = 100.0 * (double)outside / ((double)W * H);
  }
  printf("\nagainst tables over every sun (mu_s from -1; the views with pixels outside the domain's suns):\n");
  printf("%-21s | %6s | %12s | %9s | %9s | %7s\n", "view", "out %", "tables' RMSE", "net all", "seed NN", "/seed NN");
  for (int v = 0; v < nv && v < 16; ++v) {
    if (!(wide_outside[v] > 0.0)) continue;
    long n = (long)W * H * atm->n_channels;
    double nn = sf_paper_rmse(&paper, sf_paper_row(&paper, views[v].name), sf_paper_column(&paper, "Neural Net"));
    printf("%-21s | %6.1f | %12.3g | %9.3g | %9.3g | %7.3g\n", views[v].name, wide_outside[v],
           rms(wide_tables_sq[v], n), rms(wide_net_sq[v], n), nn, rms(wide_net_sq[v], n) / nn);
  }
  sf_mlp_sky_free(&net);
  sf_table_set_free(&set);
  sf_table_set_free(&set_wide);
  free(scene);
  return 0;
}
