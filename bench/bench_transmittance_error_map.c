/* Where a transmittance network's error lies (issue: neural sky, the
 * T_top target): T_top of the network (models/mlp_sky.h) against the exact
 * optical depth (models/optical_depth.h) on a 120 x 120 grid of Bruneton's
 * (x_r, x_mu), over the atmosphere stored in the weights file, printed as
 *   - the RMSE per decile of x_r (rows) and x_mu (columns);
 *   - the RMSE per channel;
 *   - the RMSE per band of the ray's lowest altitude (its tangent altitude
 *     for rays going down, the viewer's altitude otherwise): a band where
 *     the density profile has kinks (Hillaire's ozone tent at 10, 25 and
 *     40 km) shows as a band of larger error.
 *   bench_transmittance_error_map W.json */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "models/mlp_sky.h"
#include "models/optical_depth.h"
#include "models/weights_file.h"

enum { GRID = 120, DECILES = 10, BANDS = 10, BAND_KM = 10 };

int main(int argc, char **argv) {
  if (argc != 2) {
    fprintf(stderr, "usage: bench_transmittance_error_map W.json   (an mlp-transmittance weights file)\n");
    return 2;
  }
  sf_error err = {0};
  sf_weights *w = malloc(sizeof *w);
  sf_mlp_sky net;
  if (sf_weights_load_file(argv[1], "mlp-transmittance", w, &err) || sf_mlp_sky_from_weights(w, &net, &err)) {
    fprintf(stderr, "%s\n", err.message);
    return 2;
  }
  const sf_atmosphere *atm = &w->atmosphere;
  const int nch = atm->n_channels;
  double cell_sq[DECILES][DECILES] = {{0}}, channel_sq[SF_MAX_CHANNELS] = {0}, band_sq[BANDS] = {0};
  long cell_n[DECILES][DECILES] = {{0}}, band_n[BANDS] = {0};
  double worst = 0, worst_x_r = 0, worst_x_mu = 0;
  for (int i = 0; i < GRID; ++i)
    for (int j = 0; j < GRID; ++j) {
      double x_r = (i + 0.5) / GRID, x_mu = (j + 0.5) / GRID, h, mu;
      sf_mlp_bruneton_inverse(atm->bottom_radius_km, atm->top_radius_km, x_r, x_mu, &h, &mu);
      double depth[SF_MAX_CONSTITUENTS], exact[SF_MAX_CHANNELS], model[SF_MAX_CHANNELS];
      sf_optical_depth_ray(atm, h, mu, SF_RAY_END_TOP, depth);
      sf_transmittance_from_depth(atm, depth, exact);
      sf_mlp_transmittance_top(&net, h, mu, model);
      double r = atm->bottom_radius_km + h;
      double lowest = mu < 0 ? r * sqrt(1 - mu * mu) - atm->bottom_radius_km : h;
      int band = (int)(lowest / BAND_KM);
      band = band < 0 ? 0 : band >= BANDS ? BANDS - 1 : band;
      for (int c = 0; c < nch; ++c) {
        double e = model[c] - exact[c];
        cell_sq[i * DECILES / GRID][j * DECILES / GRID] += e * e;
        cell_n[i * DECILES / GRID][j * DECILES / GRID]++;
        channel_sq[c] += e * e;
        band_sq[band] += e * e;
        band_n[band]++;
        if (fabs(e) > worst) worst = fabs(e), worst_x_r = x_r, worst_x_mu = x_mu;
      }
    }
  printf("%s: T_top against the exact optical depth, %d x %d grid of (x_r, x_mu)\n", argv[1], GRID, GRID);
  printf("RMSE x 1e-4 per decile: rows x_r (ground to top), columns x_mu (up to the horizon)\n");
  double total = 0;
  for (int a = 0; a < DECILES; ++a) {
    printf("x_r %.2f-%.2f:", (double)a / DECILES, (double)(a + 1) / DECILES);
    for (int b = 0; b < DECILES; ++b) {
      printf(" %6.2f", 1e4 * sqrt(cell_sq[a][b] / (double)cell_n[a][b]));
      total += cell_sq[a][b];
    }
    printf("\n");
  }
  printf("RMSE per channel:");
  for (int c = 0; c < nch; ++c) printf(" %s %.3g", atm->channel_names[c], sqrt(channel_sq[c] / (GRID * GRID)));
  printf("\nRMSE per band of the ray's lowest altitude:\n");
  for (int k = 0; k < BANDS; ++k)
    printf("  %3d-%3d km%s: %.3g (%ld values)\n", k * BAND_KM, (k + 1) * BAND_KM, k + 1 == BANDS ? "+" : " ",
           band_n[k] ? sqrt(band_sq[k] / (double)band_n[k]) : 0.0, band_n[k]);
  printf("all: RMSE %.3g, max %.3g at x_r %.3f, x_mu %.3f\n", sqrt(total / ((double)GRID * GRID * nch)), worst,
         worst_x_r, worst_x_mu);
  sf_mlp_sky_free(&net);
  sf_weights_free(w);
  free(w);
  return 0;
}
