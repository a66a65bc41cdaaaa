#include "models/spectral_reference.h"

#include <stdlib.h>

#ifdef _OPENMP
#include <omp.h>
#endif

void sf_spectral_radiance(const sf_sky_tables *sky, size_t n, const sf_view_sample *samples, int n_threads,
                          double *radiance, unsigned char *in_atmosphere) {
  int nch = sky->atm->n_channels;
#ifdef _OPENMP
  int threads = n_threads > 0 ? n_threads : omp_get_max_threads();
#else
  int threads = 1;
  (void)n_threads;
#endif
#pragma omp parallel num_threads(threads)
  {
    sf_sky_sample *s = malloc(sizeof *s);
#pragma omp for schedule(dynamic, 64)
    for (long i = 0; i < (long)n; ++i) {
      const sf_view_sample *v = &samples[i];
      double *out = radiance + (size_t)i * nch;
      if (!s) {
        for (int ch = 0; ch < nch; ++ch) out[ch] = 0.0;
        in_atmosphere[i] = 0;
        continue;
      }
      sf_sky_lookup(sky, v->h_km, v->mu, v->mu_s, v->nu, s);
      in_atmosphere[i] = (unsigned char)s->in_atmosphere;
      for (int ch = 0; ch < nch; ++ch) out[ch] = v->scale * s->radiance[ch];
    }
    free(s);
  }
}

void sf_spectrum_to_xyz(const sf_cmf *cmf, int n, const double *lambda_nm, const double *radiance, double xyz[3]) {
  double step = n > 1 ? (lambda_nm[n - 1] - lambda_nm[0]) / (n - 1) : 1.0;
  xyz[0] = xyz[1] = xyz[2] = 0.0;
  for (int k = 0; k < n; ++k) {
    double bar[3];
    sf_cmf_at(cmf, lambda_nm[k], bar);
    for (int i = 0; i < 3; ++i) xyz[i] += bar[i] * radiance[k] * step;
  }
}

double sf_spectrum_at(int n, const double *lambda_nm, const double *radiance, double at_nm) {
  if (n == 1 || at_nm <= lambda_nm[0]) return radiance[0];
  if (at_nm >= lambda_nm[n - 1]) return radiance[n - 1];
  double step = (lambda_nm[n - 1] - lambda_nm[0]) / (n - 1);
  double pos = (at_nm - lambda_nm[0]) / step;
  int k = (int)pos;
  if (k >= n - 1) k = n - 2;
  double t = pos - k;
  return radiance[k] + t * (radiance[k + 1] - radiance[k]);
}
