/* Likely unit mistakes in a loaded atmosphere (models/atmosphere_units.h).
 * Each check names why its threshold leaves every real sky alone. */
#include "models/atmosphere_units.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>

#include "models/spectral_recipes.h"

/* The Sun's radius is 695700 km and Jupiter's 69911 km: no planet reaches
 * 1e6 km, while the smallest bodies with an atmosphere worth a sky, written
 * in metres, all pass it (Pluto 1.19e6 m, the Moon 1.74e6, Titan 2.57e6,
 * Mars 3.39e6, Earth 6.36e6). */
#define MAX_PLANET_RADIUS_KM 1e6
/* Mercury sees the Sun 0.0121 rad in radius; 0.05 rad is the Sun seen from
 * 0.09 AU. In degrees, the Sun seen from Mercury (0.69) to Jupiter (0.051)
 * is above it. */
#define MAX_SUN_RADIUS_RAD 0.05
/* Air absorbs everything below 200 nm; wavelengths in micrometres (0.44)
 * or metres are far below 100. */
#define MIN_WAVELENGTH_NM 100.0
/* Vertical optical depth of the whole atmosphere in its most opaque channel:
 * Earth 0.3 (blue), a clear Mars 0.007, Earth's coefficients per metre
 * 2.7e-4, the dusty Mars example's per metre 5e-4. */
#define MIN_OPTICAL_DEPTH 1e-3
/* A scale height above 500 km (Earth 8, Titan 20-40, Jupiter 27; SPEC §10
 * goes to 100) over which the exponential changes by less than e across the
 * atmosphere: per metre, Earth's air is 1.25e-4 and its haze 8.3e-4. */
#define MAX_SCALE_PER_METRE 2e-3
/* A layer (not the last) ten times wider than the atmosphere is thick. */
#define WIDTH_OVER_THICKNESS 10.0

static void add(sf_unit_warnings *w, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;

static void add(sf_unit_warnings *w, const char *fmt, ...) {
  if (w->count == SF_UNIT_WARNINGS_MAX) {
    ++w->dropped;
    return;
  }
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(w->text[w->count++], SF_UNIT_WARNING_LEN, fmt, ap);
  va_end(ap);
}

/* Radii in metres; returns 1 if it warned (the thickness then says nothing
 * new). */
static int check_radii(const sf_atmosphere *atm, const char *source, sf_unit_warnings *w) {
  int warned = 0;
  if (atm->bottom_radius_km >= MAX_PLANET_RADIUS_KM) {
    add(w, "%s: bottom_radius_km = %.6g: a planet of %.2g million km, larger than the Sun (695700 km); was the "
        "radius given in metres? (that is %.6g km; 6360 km is Earth)",
        source, atm->bottom_radius_km, atm->bottom_radius_km / 1e6, atm->bottom_radius_km / 1e3);
    warned = 1;
  }
  if (atm->top_radius_km >= MAX_PLANET_RADIUS_KM) {
    add(w, "%s: top_radius_km = %.6g: an atmosphere reaching %.2g million km from the planet's centre, beyond the "
        "Sun's radius (695700 km); was the radius given in metres? (that is %.6g km; 6460 km is Earth's)",
        source, atm->top_radius_km, atm->top_radius_km / 1e6, atm->top_radius_km / 1e3);
    warned = 1;
  }
  return warned;
}

/* An atmosphere thicker than its planet's radius (Titan's sky-making
 * atmosphere is a fifth of its 2575 km radius). */
static void check_thickness(const sf_atmosphere *atm, const char *source, sf_unit_warnings *w) {
  double thickness = sf_atmosphere_thickness_km(atm);
  if (!(thickness > atm->bottom_radius_km)) return;
  double top_as_metres = atm->top_radius_km / 1e3;
  char metres[160] = "";
  if (top_as_metres > atm->bottom_radius_km)
    snprintf(metres, sizeof metres, "; was it given in metres? (that is %.6g km, an atmosphere %.6g km thick)",
             top_as_metres, top_as_metres - atm->bottom_radius_km);
  add(w, "%s: top_radius_km = %.6g: the atmosphere is %.6g km thick, more than the planet's radius "
      "(bottom_radius_km = %.6g); top_radius_km is the planet's radius plus the atmosphere's thickness "
      "(Earth: 6360 + 100 = 6460)%s",
      source, atm->top_radius_km, thickness, atm->bottom_radius_km, metres);
}

static void check_sun(const sf_atmosphere *atm, const char *source, sf_unit_warnings *w) {
  double r = atm->sun_angular_radius_rad;
  if (!(r > MAX_SUN_RADIUS_RAD)) return;
  const double deg = 3.14159265358979323846 / 180.0;
  add(w, "%s: sun_angular_radius_rad = %.6g: a sun %.3g degrees in radius, %.3g times the Sun seen from Earth "
      "(0.004675 rad); was it given in degrees? (%.6g degrees is %.3g rad)",
      source, r, r / deg, r / 0.004675, r, r * deg);
}

static void check_wavelengths(const sf_atmosphere *atm, const char *source, sf_unit_warnings *w) {
  if (!atm->spectral || !(atm->wavelengths_nm[0] < MIN_WAVELENGTH_NM)) return;
  double nm = atm->wavelengths_nm[0]; /* increasing: the first is the shortest */
  add(w, "%s: channels.wavelengths_nm[0] = %.6g: shorter than %g nm, light that never reaches a sky (air absorbs "
      "everything below 200 nm); were the wavelengths given in micrometres? (%.6g um is %.6g nm)",
      source, nm, MIN_WAVELENGTH_NM, nm, nm * 1e3);
}

/* Coefficients per metre: the whole atmosphere all but a vacuum. */
static void check_optical_depth(const sf_atmosphere *atm, const char *source, sf_unit_warnings *w) {
  double thickness = sf_atmosphere_thickness_km(atm), column[SF_MAX_CONSTITUENTS];
  for (int i = 0; i < atm->n_constituents; ++i) column[i] = sf_density_column_km(&atm->constituents[i], thickness);
  double depth_max = 0.0, largest = 0.0;
  int ch_max = 0, largest_i = 0, largest_ch = 0, largest_absorbs = 0;
  for (int ch = 0; ch < atm->n_channels; ++ch) {
    double depth = 0.0;
    for (int i = 0; i < atm->n_constituents; ++i) {
      const sf_constituent *c = &atm->constituents[i];
      depth += sf_extinction(atm, i, ch) * column[i];
      for (int a = 0; a < 2; ++a) {
        double beta = a ? c->absorption[ch] : c->scattering[ch];
        if (beta > largest) largest = beta, largest_i = i, largest_ch = ch, largest_absorbs = a;
      }
    }
    if (depth > depth_max) depth_max = depth, ch_max = ch;
  }
  /* 0: a vacuum or a profile that is 0 everywhere, written so on purpose */
  if (!(depth_max > 0.0 && depth_max < MIN_OPTICAL_DEPTH)) return;
  add(w, "%s: constituent \"%s\" %s[%d] = %.6g (the largest coefficient): the whole atmosphere's vertical optical "
      "depth is at most %.3g (channel %s), nearly a vacuum; were the coefficients given per metre? (per km they "
      "are 1000 times larger; Earth's Rayleigh scattering is 0.0058 to 0.033 per km)",
      source, atm->constituents[largest_i].name, largest_absorbs ? "absorption" : "scattering", largest_ch,
      largest, depth_max, atm->channel_names[ch_max]);
}

/* One layer's exponential: growing with altitude up to the clamp at 1
 * (SPEC §4), or so slow it is a scale per metre. At most one warning. */
static void check_exponential(const sf_constituent *c, int l, double lo, double hi, double thickness,
                              const char *source, sf_unit_warnings *w) {
  const sf_density_layer *layer = &c->layers[l];
  double k = layer->exp_scale_per_km;
  if (!(layer->exp_term > 0.0) || k == 0.0) return;
  int per_metre = fabs(k) < MAX_SCALE_PER_METRE && fabs(k) * thickness < 1.0;
  /* A rising layer that stays below 1 (a haze aloft, an ozone-like peak)
   * is a shape; one that passes 1 is flat at 1 above that height. */
  if (k > 0.0 && layer->exp_term * exp(k * hi) > 1.0) {
    double meant = per_metre ? -k * 1e3 : -k;
    add(w, "%s: constituent \"%s\" density[%d].exp_scale_per_km = %.6g: the density grows with altitude (e^%.3g-fold "
        "from %.6g to %.6g km) and is clamped to 1 above %.3g km; a density that falls with altitude has a negative "
        "scale: did you mean %.6g (a scale height of %.3g km%s)?",
        source, c->name, l, k, k * (hi - lo), lo, hi, fmax(lo, -log(layer->exp_term) / k), meant, -1.0 / meant,
        per_metre ? ", the value read per metre" : "");
  } else if (per_metre) {
    add(w, "%s: constituent \"%s\" density[%d].exp_scale_per_km = %.6g: a scale height of %.4g km, over which the "
        "density changes by only %.2g%% across the %.6g km atmosphere; was it given per metre? (%.6g per km is a "
        "scale height of %.3g km)",
        source, c->name, l, k, 1.0 / fabs(k), 100.0 * (1.0 - exp(-fabs(k) * thickness)), thickness, k * 1e3,
        1.0 / fabs(k * 1e3));
  }
}

static void check_layers(const sf_atmosphere *atm, const char *source, sf_unit_warnings *w) {
  double thickness = sf_atmosphere_thickness_km(atm);
  for (int i = 0; i < atm->n_constituents; ++i) {
    const sf_constituent *c = &atm->constituents[i];
    double lo = 0.0;
    /* Bruneton 2017: layer l holds below the running sum of widths, the
     * last one for the rest; layers above the top never apply */
    for (int l = 0; l < c->n_layers && lo < thickness; ++l) {
      int last = l == c->n_layers - 1;
      double width = c->layers[l].width_km, hi = last ? thickness : fmin(lo + width, thickness);
      check_exponential(c, l, lo, hi, thickness, source, w);
      if (!last && width > WIDTH_OVER_THICKNESS * thickness && width / 1e3 < thickness)
        add(w, "%s: constituent \"%s\" density[%d].width_km = %.6g: the layer reaches %.6g km, far above the top of "
            "the %.6g km atmosphere, so the layers after it never apply; was the width given in metres? (that is "
            "%.6g km)",
            source, c->name, l, width, lo + width, thickness, width / 1e3);
      lo += width;
    }
  }
}

void sf_atmosphere_unit_warnings(const sf_atmosphere *atm, const char *source, sf_unit_warnings *out) {
  out->count = 0;
  out->dropped = 0;
  if (!check_radii(atm, source, out)) check_thickness(atm, source, out);
  check_sun(atm, source, out);
  check_wavelengths(atm, source, out);
  check_optical_depth(atm, source, out);
  check_layers(atm, source, out);
}
