/* Spectral recipes of the atmosphere file (SPEC §4) against published
 * values and closed forms, and the shipped tables' documented checks. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "models/atmosphere_file.h"
#include "models/spectral_atmosphere.h"
#include "models/spectral_data.h"
#include "models/spectral_recipes.h"
#include "tests/check.h"

static const char *const spectral_json =
    "{\"name\": \"recipes\", \"bottom_radius_km\": 6360, \"top_radius_km\": 6460,\n"
    " \"channels\": {\"wavelengths_nm\": [440, 550, 600, 680]},\n"
    " \"sun_irradiance\": {\"recipe\": \"solar_astm_g173\", \"bin_nm\": 10},\n"
    " \"constituents\": [\n"
    "  {\"name\": \"rayleigh\", \"scattering\": {\"recipe\": \"rayleigh_lambda4\", \"reference_nm\": 1000,"
    "    \"reference_per_km\": 1.24062e-3}, \"absorption\": 0, \"phase\": {\"kind\": \"rayleigh\"},\n"
    "   \"density\": [{\"exp_term\": 1, \"exp_scale_per_km\": -0.125}]},\n"
    "  {\"name\": \"bucholtz\", \"scattering\": {\"recipe\": \"rayleigh_bucholtz\"}, \"absorption\": 0,"
    "   \"phase\": {\"kind\": \"rayleigh\"}, \"density\": [{\"exp_term\": 1, \"exp_scale_per_km\": -0.125}]},\n"
    "  {\"name\": \"mie\", \"scattering\": {\"recipe\": \"angstrom\", \"reference_nm\": 550, \"reference_per_km\": 0.004,"
    "    \"exponent\": 1.3}, \"absorption\": {\"recipe\": \"constant\", \"value\": 4.44e-4},"
    "   \"phase\": {\"kind\": \"cornette_shanks\", \"g\": 0.8},"
    "   \"density\": [{\"exp_term\": 1, \"exp_scale_per_km\": -0.8333333}]},\n"
    "  {\"name\": \"ozone\", \"scattering\": 0, \"absorption\": {\"recipe\": \"ozone_cross_section\", \"column_du\": %s},\n"
    "   \"density\": [{\"width_km\": 25, \"linear_per_km\": 0.0666667, \"constant\": -0.6666667},\n"
    "               {\"width_km\": 0, \"linear_per_km\": -0.0666667, \"constant\": 2.6666667}]}]}\n";

static int load_with_column(const char *du, sf_atmosphere *atm, sf_error *err) {
  char text[4096];
  snprintf(text, sizeof text, spectral_json, du);
  return sf_atmosphere_load_string(text, "recipes.json", atm, err);
}

static void expect_error(const char *json, const char *needle) {
  sf_atmosphere *atm = malloc(sizeof *atm);
  sf_error err = {0};
  int rc = sf_atmosphere_load_string(json, "bad.json", atm, &err);
  printf("error: %s\n", err.message);
  CHECK(rc == SF_ERR_INPUT);
  CHECK(strstr(err.message, needle) != NULL);
  free(atm);
}

int main(void) {
  sf_error err = {0};
  /* CIE 1931 table (data README): 5 nm x sum ybar = 106.857 */
  sf_cmf *cmf = malloc(sizeof *cmf);
  CHECK(sf_cmf_load(cmf, &err) == 0);
  double sum_y = 0.0;
  for (int i = 0; i < cmf->y.n; ++i) sum_y += 5.0 * cmf->y.value[i];
  CHECK_REL(sum_y, 106.857, 1e-5);
  double bar[3];
  sf_cmf_at(cmf, 555.0, bar);
  CHECK_ABS(bar[1], 1.0, 1e-9);   /* ybar(555) = 1 */
  free(cmf);

  /* Bucholtz 1995 (data README): beta_s(550) = 0.01149 / km */
  double l550 = 550.0, beta = 0.0;
  CHECK(sf_recipe_rayleigh_bucholtz(1, &l550, 1.0, &beta, &err) == 0);
  CHECK_REL(beta, 0.01149, 1e-3);
  /* seed 003 eq. 4.2: the formula with standard air's n(550) = 1.0002779
   * (Peck & Reeder) and N_s = 2.54743e25 / m³ times the King factor of
   * depolarisation 0.0279, (6 + 3 rho)/(6 - 7 rho) = 1.0481, is Bucholtz's value */
  double king = (6.0 + 3.0 * 0.0279) / (6.0 - 7.0 * 0.0279);
  CHECK_REL(sf_rayleigh_formula_per_km(550.0, 1.0002779, 2.54743e25) * king, beta, 3e-3);
  /* log-log interpolation: between samples the local exponent ~4.09 */
  double l555 = 555.0, beta555 = 0.0;
  CHECK(sf_recipe_rayleigh_bucholtz(1, &l555, 1.0, &beta555, &err) == 0);
  CHECK_REL(beta555, beta * pow(550.0 / 555.0, 4.09), 1e-3);
  /* lambda^-4 closed form: reference scaled by the fourth power */
  CHECK_REL(sf_rayleigh_lambda4_per_km(400.0, 800.0, 1.0), 16.0, 1e-15);
  CHECK_REL(sf_rayleigh_formula_per_km(400.0, 1.0003, 2.5e25) / sf_rayleigh_formula_per_km(800.0, 1.0003, 2.5e25),
            16.0, 1e-14);
  CHECK_REL(sf_angstrom_per_km(1100.0, 550.0, 2.0, 1.0), 1.0, 1e-15);

  /* the loaded file: Bruneton's lambda^-4 gives the default atmosphere's
   * Rayleigh triplet, 300 DU on the tent gives its ozone triplet (data
   * README: 6.50e-7 / 1.881e-6 / 8.50e-8 per m at 680/550/440 nm) */
  sf_atmosphere *atm = malloc(sizeof *atm), *atm2 = malloc(sizeof *atm2), *back = malloc(sizeof *back);
  CHECK(load_with_column("300", atm, &err) == 0);
  printf("%s\n", err.message);
  const sf_constituent *ray = &atm->constituents[0], *buch = &atm->constituents[1],
                       *mie = &atm->constituents[2], *oz = &atm->constituents[3];
  CHECK_REL(ray->scattering[0], 33.1e-3, 1e-3);
  CHECK_REL(ray->scattering[1], 13.558e-3, 1e-4);
  CHECK_REL(ray->scattering[3], 5.802e-3, 1e-4);
  CHECK_REL(buch->scattering[1], beta, 0.0);
  CHECK_REL(mie->scattering[1], 0.004, 1e-15);
  CHECK_REL(mie->scattering[3], 0.004 * pow(680.0 / 550.0, -1.3), 1e-14);
  CHECK_REL(mie->absorption[2], 4.44e-4, 0.0);
  /* the tent's column is 15 km; N = 300 DU * 2.687e20 / 15 km = 5.374e18 / m³ */
  CHECK_REL(sf_density_column_km(oz, 100.0), 15.0, 1e-6);
  /* exactly, the 7-digit tent's area: rising from 0 at 0.6666667 / 0.0666667
   * km, clamped at 1 from 1.6666667 / 0.0666667 km to 25, then falling from
   * 2.6666667 - 25 x 0.0666667 to 0 at 2.6666667 / 0.0666667 km */
  double z0 = 0.6666667 / 0.0666667, z1 = 1.6666667 / 0.0666667, v25 = 2.6666667 - 25.0 * 0.0666667;
  double tent = 0.5 * (z1 - z0) + (25.0 - z1) + 0.5 * v25 * (2.6666667 / 0.0666667 - 25.0);
  CHECK_REL(sf_density_column_km(oz, 100.0), tent, 1e-12);
  /* at any thickness: the tent in a 1e8 km atmosphere (a trapezoid over the
   * whole thickness had stepped over it: "integrates to 0"), and a 10 m
   * scale height in 100 km, 0.01 (1 - e^-10000) (it had been 1.2e-4 high) */
  CHECK_REL(sf_density_column_km(oz, 1e8), tent, 1e-12);
  sf_constituent thin;
  memset(&thin, 0, sizeof thin);
  thin.n_layers = 1;
  thin.layers[0] = (sf_density_layer){0.0, 1.0, -100.0, 0.0, 0.0};
  CHECK_REL(sf_density_column_km(&thin, 100.0), 0.01, 1e-12);
  /* Earth's Rayleigh profile, 8 km, in 3e6 km: a single panel over it all
   * had seen 0 at every node ("integrates to 0") */
  thin.layers[0].exp_scale_per_km = -0.125;
  CHECK_REL(sf_density_column_km(&thin, 3e6), 8.0, 1e-12);
  CHECK_REL(sf_ozone_peak_number_density(300.0, 15.0), 5.374e18, 1e-12);
  CHECK_REL(oz->absorption[0], 0.085e-3, 2e-3);
  CHECK_REL(oz->absorption[1], 1.881e-3, 1e-3);
  CHECK_REL(oz->absorption[3], 0.650e-3, 1e-3);
  /* vertical ozone optical depth of 300 DU at 600 nm = 0.0405 (data README) */
  CHECK_REL(oz->absorption[2] * sf_density_column_km(oz, 100.0), 0.0405, 2e-3);
  /* ASTM ETR mean over [545, 555] nm against an independent sample mean of
   * the same file's 1 nm rows 545..555 (trapezoid weights 1/2 at the ends) */
  sf_spectrum *astm = malloc(sizeof *astm);
  CHECK(sf_spectrum_load("astm_g173.csv", "etr", astm, &err) == 0);
  double trap = 0.0;
  for (int i = 0; i < astm->n; ++i)
    if (astm->lambda_nm[i] >= 545.0 && astm->lambda_nm[i] <= 555.0)
      trap += (astm->lambda_nm[i] == 545.0 || astm->lambda_nm[i] == 555.0 ? 0.5 : 1.0) * astm->value[i];
  CHECK_REL(atm->sun_irradiance[1], trap / 10.0, 1e-12);
  /* and the 10 nm bin [550, 560) of solar_irradiance.csv, 1.8504, the mean of
   * the 1 nm samples 550..559: the interpolant's mean over the samples'
   * own extent [549.5, 559.5] agrees to the spectrum's fine structure */
  CHECK_REL(sf_spectrum_window_mean(astm, 549.5, 559.5), 1.8504, 5e-4);
  free(astm);

  /* canonical JSON holds the derived numbers, loads back identical; the
   * hash follows the data (301 DU differs) */
  char *json = sf_atmosphere_to_json(atm);
  CHECK(json && strstr(json, "\"recipe\"") == NULL);
  CHECK(sf_atmosphere_load_string(json, "canonical", back, &err) == 0);
  CHECK(sf_atmosphere_hash(back) == sf_atmosphere_hash(atm));
  CHECK(memcmp(back->constituents[3].absorption, oz->absorption, sizeof oz->absorption) == 0);
  free(json);
  CHECK(load_with_column("301", atm2, &err) == 0);
  CHECK(sf_atmosphere_hash(atm2) != sf_atmosphere_hash(atm));
  CHECK_REL(atm2->constituents[3].absorption[1], oz->absorption[1] * 301.0 / 300.0, 1e-12);

  /* bad input names the key path */
  expect_error("{\"bottom_radius_km\": 6360, \"top_radius_km\": 6460, \"constituents\": [{\"name\": \"r\","
               " \"scattering\": {\"recipe\": \"rayleigh_bucholtz\"}, \"absorption\": 0, \"phase\": {\"kind\": \"rayleigh\"},"
               " \"density\": [{\"exp_term\": 1}]}]}",
               "constituents[0].scattering.recipe: recipe \"rayleigh_bucholtz\" needs spectral channels");
  expect_error("{\"bottom_radius_km\": 6360, \"top_radius_km\": 6460, \"channels\": {\"wavelengths_nm\": [550]},"
               " \"constituents\": [{\"name\": \"r\", \"scattering\": {\"recipe\": \"rayleigh_magic\"}, \"absorption\": 0,"
               " \"phase\": {\"kind\": \"rayleigh\"}, \"density\": [{\"exp_term\": 1}]}]}",
               "constituents[0].scattering.recipe: unknown recipe \"rayleigh_magic\"");
  expect_error("{\"bottom_radius_km\": 6360, \"top_radius_km\": 6460, \"channels\": {\"wavelengths_nm\": [5000]},"
               " \"constituents\": [{\"name\": \"r\", \"scattering\": {\"recipe\": \"rayleigh_bucholtz\"}, \"absorption\": 0,"
               " \"phase\": {\"kind\": \"rayleigh\"}, \"density\": [{\"exp_term\": 1}]}]}",
               "constituents[0].scattering: wavelength 5000 nm is outside rayleigh_bucholtz.csv");
  /* a refractive index below 1 squares to the scattering of one above */
  expect_error("{\"bottom_radius_km\": 6360, \"top_radius_km\": 6460, \"channels\": {\"wavelengths_nm\": [550]},"
               " \"constituents\": [{\"name\": \"r\", \"scattering\": {\"recipe\": \"rayleigh_formula\", \"refractive_index\": 0.5,"
               " \"number_density_per_m3\": 2.5e25}, \"absorption\": 0, \"phase\": {\"kind\": \"rayleigh\"},"
               " \"density\": [{\"exp_term\": 1}]}]}",
               "constituents[0].scattering.refractive_index: must be > 1");
  expect_error("{\"bottom_radius_km\": 6360, \"top_radius_km\": 6460, \"channels\": {\"wavelengths_nm\": [550]},"
               " \"constituents\": [{\"name\": \"o\", \"scattering\": 0, \"absorption\": {\"recipe\": \"ozone_cross_section\","
               " \"column_du\": -3}, \"density\": [{\"constant\": 1}]}]}",
               "constituents[0].absorption.column_du: negative value");
  expect_error("{\"bottom_radius_km\": 6360, \"top_radius_km\": 6460, \"channels\": {\"wavelengths_nm\": [550]},"
               " \"constituents\": [{\"name\": \"o\", \"scattering\": 0, \"absorption\": {\"recipe\": \"angstrom\","
               " \"reference_nm\": 550, \"reference_per_km\": 1, \"colour\": 2}, \"density\": [{\"constant\": 1}]}]}",
               "colour");
  /* An RGB atmosphere's spectral counterpart: the default's ozone triplet
   * becomes ozone's spectrum, 300 DU (0.0405 at 600 nm, data README); a
   * grey absorber beside it stays grey (it had been given ozone's
   * spectrum too: 5.6e-5 at 440 nm for its 1e-3). */
  sf_atmosphere_default(atm);
  int i_ozone = -1;
  for (int i = 0; i < atm->n_constituents; ++i)
    if (strcmp(atm->constituents[i].name, "ozone") == 0) i_ozone = i;
  CHECK(i_ozone >= 0 && atm->n_constituents < SF_MAX_CONSTITUENTS);
  if (i_ozone >= 0 && atm->n_constituents < SF_MAX_CONSTITUENTS) {
    sf_constituent *soot = &atm->constituents[atm->n_constituents++];
    *soot = atm->constituents[i_ozone];
    snprintf(soot->name, sizeof soot->name, "soot");
    for (int ch = 0; ch < 3; ++ch) soot->absorption[ch] = 1e-3;
    double nm[SF_MAX_CHANNELS];
    int n = sf_spectral_grid(SF_SPECTRAL_MIN_NM, SF_SPECTRAL_MAX_NM, SF_SPECTRAL_STEP_NM, nm);
    CHECK(sf_spectral_atmosphere(atm, n, nm, back, &err) == 0);
    const sf_constituent *oz_spec = &back->constituents[i_ozone], *soot_spec = &back->constituents[atm->n_constituents - 1];
    int i600 = (int)((600.0 - SF_SPECTRAL_MIN_NM) / SF_SPECTRAL_STEP_NM + 0.5);
    CHECK(nm[i600] == 600.0);
    printf("spectral counterpart: ozone tau(600 nm) = %.5f; grey absorber at 400/440/600/700 nm: %g %g %g %g\n",
           oz_spec->absorption[i600] * sf_density_column_km(oz_spec, 100.0), soot_spec->absorption[8],
           soot_spec->absorption[16], soot_spec->absorption[i600], soot_spec->absorption[68]);
    CHECK_REL(oz_spec->absorption[i600] * sf_density_column_km(oz_spec, 100.0), 0.0405, 2e-3);
    double worst = 0.0;
    for (int ch = 0; ch < n; ++ch) worst = fmax(worst, fabs(soot_spec->absorption[ch] / 1e-3 - 1.0));
    CHECK(worst < 1e-12);
  }
  free(atm);
  free(atm2);
  free(back);
  return check_summary();
}
