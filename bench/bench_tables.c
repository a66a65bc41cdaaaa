/* Benchmark of the reference tables at the default resolution (issue
 * "reference tables"): time of each stage, accuracy of the entries against
 * the adaptive references, the scattering orders, sky radiance against the
 * Monte Carlo path tracer at a few exact entries, and peak memory.
 *
 *   bench_tables [--threads N] [--quick]
 *
 * Targets: transmittance 256x64 at <= 1e-7 relative in <= 0.1 s; single
 * scattering 32x128x32x8 in <= 5 s; 4 orders of multiple scattering in <= 60
 * s. --quick skips the Leenman tables and the path tracer. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <time.h>

#include "data/precompute_multiple.h"
#include "data/precompute_single.h"
#include "data/precompute_transmittance.h"
#include "data/scattering_setup.h"
#include "data/sky_lookup.h"
#include "data/table_params.h"
#include "models/atmosphere_file.h"
#include "models/optical_depth.h"
#include "models/path_tracer.h"
#include "models/phase.h"
#include "models/ray_geometry.h"
#include "models/single_scattering.h"
#include "util/clock.h"

static double peak_mib(void) {
  struct rusage u;
  getrusage(RUSAGE_SELF, &u);
  return u.ru_maxrss / 1024.0;   /* Linux: kilobytes */
}

/* A stage's wall and CPU time. */
typedef struct stopwatch { double wall, cpu; } stopwatch;
static stopwatch start(void) { return (stopwatch){sf_wall_seconds(), sf_cpu_seconds()}; }
static stopwatch stop(stopwatch s) { return (stopwatch){sf_wall_seconds() - s.wall, sf_cpu_seconds() - s.cpu}; }

static void transmittance_bench(const sf_atmosphere *atm, sf_parameterization kind, int threads) {
  sf_table_resolution res;
  sf_table_resolution_default(&res);
  sf_table_params p;
  sf_table_params_make(&p, atm, kind, &res);
  sf_table_desc desc;
  sf_error err = {0};
  sf_table t;
  sf_params_transmittance_desc(&p, atm, &desc, &err);
  sf_table_init(&t, &desc, NULL, 0, &err);
  sf_precompute_options opt = {threads, NULL, NULL};
  stopwatch w = start();
  sf_precompute_transmittance(atm, &p, &opt, &t, &err);
  w = stop(w);
  double worst = 0.0, sum = 0.0;
  long n = 0;
  for (int i1 = 0; i1 < desc.axes[1].size; ++i1)
    for (int i0 = 0; i0 < desc.axes[0].size; ++i0) {
      int index[2] = {i0, i1};
      double pos[2] = {i0, i1}, h, mu, depth[SF_MAX_CONSTITUENTS], want[SF_MAX_CHANNELS];
      sf_params_transmittance_coord(&p, pos, &h, &mu);
      if (kind == SF_PARAM_LEENMAN) {
        sf_optical_depth_ray(atm, h, mu, SF_RAY_END_NEAREST, depth);
      } else {
        double r = atm->bottom_radius_km + h, t_near, t_far = 0.0;
        sf_ray_sphere_intersections(r, mu, atm->top_radius_km, &t_near, &t_far);
        sf_optical_depth_segment(atm, r, mu, 0.0, t_far, depth);
      }
      sf_transmittance_from_depth(atm, depth, want);
      const float *got = sf_table_at(&t, index);
      for (int ch = 0; ch < atm->n_channels; ++ch) {
        double e = fabs(got[ch] - want[ch]) / want[ch];
        worst = fmax(worst, e);
        sum += e;
        ++n;
      }
    }
  printf("| transmittance %-8s | %dx%d | %.3f s | %.3f s | max rel %.2e, mean %.2e (float32 entries vs "
         "sf_optical_depth_ray) | <= 0.1 s at <= 1e-7 |\n", sf_parameterization_name(kind),
         res.transmittance_mu, res.transmittance_h, w.wall, w.cpu, worst, sum / n);
  sf_table_free(&t);
}

/* Single-scattering entries against sf_single_scattering at n_samples
 * random entries (exact entries, no interpolation). */
static void single_accuracy(const sf_atmosphere *atm, const sf_scattering_setup *s, const sf_table_params *p,
                            const sf_table *tables, int n_samples, double *max_rel, double *mean_rel,
                            double *max_rel_bright) {
  const sf_table_desc *d = &tables[0].desc;
  int nch = atm->n_channels, ns = s->n_scattering;
  double *want = malloc(sizeof(double) * (size_t)n_samples * ns * nch);
  double *got = malloc(sizeof(double) * (size_t)n_samples * ns * nch);
  double scale[SF_MAX_CONSTITUENTS * SF_MAX_CHANNELS] = {0};
  unsigned long long state = 0x9e3779b97f4a7c15ull;
  for (int q = 0; q < n_samples; ++q) {
    int index[4];
    for (int a = 0; a < 4; ++a) {
      state = state * 6364136223846793005ull + 1442695040888963407ull;
      index[a] = (int)((state >> 33) % (unsigned long long)d->axes[a].size);
    }
    double pos[4] = {index[0], index[1], index[2], index[3]};
    sf_scattering_coord c;
    sf_params_scattering_coord(p, pos, &c);
    double r = atm->bottom_radius_km + c.h;
    sf_view_ray ray = {r, c.mu, 0.0, sf_ray_end_distance(atm, r, c.mu, c.hits_ground), c.hits_ground};
    double ref[SF_MAX_CONSTITUENTS * SF_MAX_CHANNELS];
    sf_single_scattering(atm, &ray, c.mu_s, c.nu, ref);
    for (int k = 0; k < ns; ++k)
      for (int ch = 0; ch < nch; ++ch) {
        size_t i = ((size_t)q * ns + k) * nch + ch;
        want[i] = ref[s->scattering[k] * nch + ch];
        got[i] = sf_table_at(&tables[k], index)[ch];
        scale[k * nch + ch] = fmax(scale[k * nch + ch], want[i]);
      }
  }
  *max_rel = *mean_rel = *max_rel_bright = 0.0;
  long n = 0;
  for (int q = 0; q < n_samples; ++q)
    for (int k = 0; k < ns * nch; ++k) {
      size_t i = (size_t)q * ns * nch + k;
      double e = fabs(got[i] - want[i]) / fmax(want[i], 1e-6 * scale[k]);
      *max_rel = fmax(*max_rel, e);
      if (want[i] > 1e-3 * scale[k]) *max_rel_bright = fmax(*max_rel_bright, e);
      *mean_rel += e;
      ++n;
    }
  *mean_rel /= n;
  free(want);
  free(got);
}

static int init_singles(const sf_atmosphere *atm, const sf_scattering_setup *s, const sf_table_params *p,
                        sf_table *tables) {
  sf_error err = {0};
  for (int k = 0; k < s->n_scattering; ++k) {
    char name[SF_TABLE_NAME_LEN];
    sf_table_desc desc;
    if (sf_single_table_name(&atm->constituents[s->scattering[k]], name, &err) ||
        sf_params_scattering_desc(p, atm, name, &desc, &err) || sf_table_init(&tables[k], &desc, NULL, 0, &err)) {
      fprintf(stderr, "%s\n", err.message);
      return -1;
    }
  }
  return 0;
}

int main(int argc, char **argv) {
  int threads = 0, quick = 0;
  for (int i = 1; i < argc; ++i) {
    if (strcmp(argv[i], "--threads") == 0 && i + 1 < argc) threads = atoi(argv[++i]);
    else if (strcmp(argv[i], "--quick") == 0) quick = 1;
    else {
      fprintf(stderr, "usage: bench_tables [--threads N] [--quick]\n");
      return 2;
    }
  }
  sf_atmosphere atm;
  sf_atmosphere_default(&atm);
  sf_precompute_options opt = {threads, NULL, NULL};
  sf_error err = {0};
  printf("threads: %d (0 = OpenMP default)\n\n", threads);
  printf("| stage | resolution | wall | CPU | result | target |\n|---|---|---|---|---|---|\n");
  transmittance_bench(&atm, SF_PARAM_BRUNETON, threads);
  transmittance_bench(&atm, SF_PARAM_LEENMAN, threads);

  stopwatch w = start();
  sf_scattering_setup setup;
  if (sf_scattering_setup_init(&setup, &atm, &opt, &err)) {
    fprintf(stderr, "%s\n", err.message);
    return 1;
  }
  w = stop(w);
  printf("| sun optical-depth grid | %dx%d | %.3f s | %.3f s | (used by every scattering integral) | |\n",
         SF_DEPTH_GRID_MU, SF_DEPTH_GRID_H, w.wall, w.cpu);

  sf_table_resolution res;
  sf_table_resolution_default(&res);
  int n_kinds = quick ? 1 : 2;
  for (int kind = 0; kind < n_kinds; ++kind) {
    sf_table_params p;
    sf_table_params_make(&p, &atm, (sf_parameterization)kind, &res);
    sf_table singles[SF_MAX_CONSTITUENTS];
    memset(singles, 0, sizeof singles);
    if (init_singles(&atm, &setup, &p, singles)) return 1;
    w = start();
    sf_precompute_single(&setup, &p, &opt, singles, &err);
    w = stop(w);
    double max_rel, mean_rel, max_bright;
    int n_samples = quick ? 500 : 2000;
    single_accuracy(&atm, &setup, &p, singles, n_samples, &max_rel, &mean_rel, &max_bright);
    printf("| single scattering %-8s (%d tables) | 32x128x32x8 | %.2f s | %.2f s | vs sf_single_scattering "
           "at %d random entries x %d values: max rel %.2e (values > 1e-3 of max: %.2e), mean %.2e "
           "(floor 1e-6 of the channel max) | <= 5 s |\n",
           sf_parameterization_name((sf_parameterization)kind), setup.n_scattering, w.wall, w.cpu, n_samples,
           setup.n_scattering * atm.n_channels, max_rel, max_bright, mean_rel);

    /* multiple scattering; Leenman computes its internal Bruneton singles */
    sf_table_params internal;
    sf_multiple_internal_params(&p, &internal);
    sf_table internal_singles[SF_MAX_CONSTITUENTS];
    memset(internal_singles, 0, sizeof internal_singles);
    const sf_table *source = singles;
    w = start();
    if (kind == SF_PARAM_LEENMAN) {
      if (init_singles(&atm, &setup, &internal, internal_singles)) return 1;
      sf_precompute_single(&setup, &internal, &opt, internal_singles, &err);
      source = internal_singles;
    }
    sf_table multiple, irradiance;
    sf_table_desc d;
    sf_params_scattering_desc(&p, &atm, "multiple", &d, &err);
    sf_table_init(&multiple, &d, NULL, 0, &err);
    sf_params_irradiance_desc(&p, &atm, &d, &err);
    sf_table_init(&irradiance, &d, NULL, 0, &err);
    sf_multiple_options mo = {4, 0.0};
    sf_multiple_report report;
    if (sf_precompute_multiple(&setup, &p, source, &mo, &opt, &multiple, &irradiance, &report, &err)) {
      fprintf(stderr, "%s\n", err.message);
      return 1;
    }
    w = stop(w);
    char orders[256] = "";
    for (int k = 2; k <= report.highest_order; ++k) {
      size_t len = strlen(orders);
      snprintf(orders + len, sizeof orders - len, "%sorder %d adds %.3g", k > 2 ? ", " : "", k,
               report.added_fraction[k]);
    }
    printf("| multiple scattering %-8s, 4 orders%s | 32x128x32x8 | %.2f s | %.2f s | %s of the sky radiance "
           "so far | <= 60 s |\n", sf_parameterization_name((sf_parameterization)kind),
           kind == SF_PARAM_LEENMAN ? " (incl. internal Bruneton singles)" : "", w.wall, w.cpu, orders);

    if (!quick && kind == SF_PARAM_BRUNETON) {
      /* sky radiance (all orders <= 4) at exact entries against the path
       * tracer limited to 4 orders */
      sf_sky_tables sky;
      memset(&sky, 0, sizeof sky);
      sky.atm = &atm;
      sky.params = p;
      sky.n_single = setup.n_scattering;
      for (int k = 0; k < setup.n_scattering; ++k) {
        sky.single_constituent[k] = setup.scattering[k];
        sky.single[k] = &singles[k];
      }
      sky.multiple = &multiple;
      int entries[5][4] = {{20, 64 + 10, 4, 0}, {28, 64 + 40, 2, 0}, {12, 64 + 2, 6, 0},
                           {20, 64 + 30, 7, 10}, {24, 20, 3, 20}};
      printf("\nsky radiance (single + orders 2..4) at exact table entries vs the path tracer (max_order 4, "
             "1e5 paths per channel):\n\n| h km | mu | mu_s | nu | channel | tables | path tracer | "
             "difference | sigma |\n|---|---|---|---|---|---|---|---|---|\n");
      for (int e = 0; e < 5; ++e) {
        double pos[4] = {entries[e][0], entries[e][1], entries[e][2], entries[e][3]};
        sf_scattering_coord c;
        sf_params_scattering_coord(&p, pos, &c);
        double nu = sf_clamp_nu(c.mu, c.mu_s, c.nu);
        sf_sky_sample sample;
        sf_sky_lookup(&sky, c.h, c.mu, c.mu_s, nu, &sample);
        sf_path_tracer_options po = {100000, 7 + e, 4, threads};
        sf_path_tracer_result mc;
        if (sf_path_trace_sky_radiance(&atm, c.h, c.mu, c.mu_s, nu, &po, &mc, &err)) {
          printf("path tracer failed: %s\n", err.message);
          break;
        }
        for (int ch = 0; ch < atm.n_channels; ++ch)
          printf("| %.3g | %.4f | %.4f | %.4f | %s | %.5g | %.5g | %+.2f%% | %.2f%% |\n", c.h, c.mu, c.mu_s, nu,
                 atm.channel_names[ch], sample.radiance[ch], mc.radiance[ch],
                 100.0 * (sample.radiance[ch] / mc.radiance[ch] - 1.0), 100.0 * mc.std_error[ch] / mc.radiance[ch]);
      }
      printf("\n");
    }
    sf_table_free(&multiple);
    sf_table_free(&irradiance);
    for (int k = 0; k < SF_MAX_CONSTITUENTS; ++k) {
      sf_table_free(&singles[k]);
      sf_table_free(&internal_singles[k]);
    }
  }
  sf_scattering_setup_free(&setup);
  printf("\npeak memory (getrusage ru_maxrss): %.0f MiB\n", peak_mib());
  return 0;
}
