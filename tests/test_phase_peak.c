/* data/phase_peak.h: the mass of a phase function's peak above its value
 * on the edge of the 12-degree cone, against the closed form for
 * Henyey-Greenstein lobes (forward and backward), and which atmospheres the
 * tables warn about: Earth's (Rayleigh, Mie as Cornette-Shanks 0.8) not, a
 * g-0.99 haze yes. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "data/phase_peak.h"
#include "models/atmosphere_file.h"
#include "models/phase.h"
#include "tests/check.h"
#include "util/constants.h"

/* 2 pi * integral over c in [c_t, 1] of p_HG(|g|, c) - p_t:
 * (1 - g^2) / (2 |g|) (1 / (1 - |g|) - k_t^(-1/2)) - 2 pi p_t (1 - c_t),
 * k_t = 1 + g^2 - 2 |g| c_t (a lobe of g < 0 is the same about nu = -1). */
static double hg_mass(double g, double c_t) {
  double a = fabs(g), k_t = 1.0 + a * a - 2.0 * a * c_t;
  double p_t = (1.0 - a * a) / (4.0 * SF_PI * k_t * sqrt(k_t));
  return (1.0 - a * a) / (2.0 * a) * (1.0 / (1.0 - a) - 1.0 / sqrt(k_t)) - 2.0 * SF_PI * p_t * (1.0 - c_t);
}

int main(void) {
  double c_t = cos(SF_PHASE_PEAK_CONE_DEG * SF_PI / 180.0);
  const double gs[] = {0.5, 0.85, 0.95, 0.99, 0.9999, -0.99};
  for (int i = 0; i < 6; ++i) {
    sf_phase p = {.kind = SF_PHASE_HENYEY_GREENSTEIN, .g = gs[i]};
    sf_phase_peak fw, bw;
    sf_phase_peaks(&p, &fw, &bw);
    const sf_phase_peak *peak = gs[i] > 0 ? &fw : &bw, *other = gs[i] > 0 ? &bw : &fw;
    printf("HG g %g:\n", gs[i]);
    /* the phase function takes nu = 1 - x, which rounds x to 1.1e-16: a
     * relative 1e-8 of a lobe 1e-8 wide (g 0.9999) */
    CHECK_REL(peak->fraction, hg_mass(gs[i], c_t), fabs(gs[i]) > 0.999 ? 1e-8 : 1e-10);
    CHECK(other->fraction == 0.0 && !other->active);   /* the far side of a lobe falls towards its axis */
    CHECK(peak->active == (fabs(gs[i]) >= 0.85));
  }
  /* Earth: Rayleigh has no peak to speak of, Mie's (f 0.128) is resolved */
  sf_atmosphere earth;
  sf_atmosphere_default(&earth);
  char text[512] = "";
  CHECK(sf_phase_peaks_note(&earth, text, sizeof text) == 0);
  for (int i = 0; i < earth.n_constituents; ++i) {
    sf_phase_peak fw, bw;
    sf_phase_peaks(&earth.constituents[i].phase, &fw, &bw);
    printf("earth %s: forward %.4f backward %.4f\n", earth.constituents[i].name, fw.fraction, bw.fraction);
    CHECK(!fw.active && !bw.active);
  }
  /* Earth's Mie at g 0.99: named, with its fraction (Cornette-Shanks: 0.9385) */
  for (int i = 0; i < earth.n_constituents; ++i)
    if (strcmp(earth.constituents[i].name, "mie") == 0) earth.constituents[i].phase.g = 0.99;
  CHECK(sf_phase_peaks_note(&earth, text, sizeof text) == 1);
  printf("note: %s\n", text);
  CHECK(strstr(text, "mie's phase function puts 0.94") != NULL && strstr(text, "forward") != NULL);
  return check_summary();
}
