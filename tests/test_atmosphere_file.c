/* The atmosphere file (SPEC §4): the built-in default against the numbers
 * printed in the SPEC, "base": "default" merging, the canonical text and its
 * hash, and one rejected file per class of invalid input. */
#include "models/atmosphere_file.h"

#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "tests/check.h"
#include "util/hash64.h"

/* Test JSON is written with single quotes to stay readable in C. */
static char *json_q(const char *text) {
  char *s = malloc(strlen(text) + 1);
  for (size_t i = 0;; ++i) {
    s[i] = text[i] == '\'' ? '"' : text[i];
    if (!text[i]) break;
  }
  return s;
}

static sf_atmosphere *load_ok(const char *label, const char *single_quoted) {
  char *text = json_q(single_quoted);
  sf_atmosphere *atm = calloc(1, sizeof *atm);
  sf_error err;
  sf_error_clear(&err);
  int rc = sf_atmosphere_load_string(text, "good.json", atm, &err);
  printf("%-34s rc=%d %s\n", label, rc, rc ? err.message : "(loaded)");
  CHECK(rc == 0);
  free(text);
  return atm;
}

/* A rejected file must give SF_ERR_INPUT, a one-line message
 * "bad.json: <path>: <problem containing word>", and leave *out untouched. */
static void expect_error(const char *label, const char *single_quoted, const char *want_path,
                         const char *want_word) {
  char *text = json_q(single_quoted);
  sf_atmosphere *out = malloc(sizeof *out), *before = malloc(sizeof *before);
  memset(out, 0x5a, sizeof *out);
  memcpy(before, out, sizeof *out);
  sf_error err;
  sf_error_clear(&err);
  int rc = sf_atmosphere_load_string(text, "bad.json", out, &err);
  printf("%-34s rc=%d %s\n", label, rc, err.message);
  char want_prefix[400];
  snprintf(want_prefix, sizeof want_prefix, "bad.json: %s: ", want_path);
  int ok = rc == SF_ERR_INPUT && err.status == SF_ERR_INPUT &&
           strncmp(err.message, want_prefix, strlen(want_prefix)) == 0 &&
           strstr(err.message + strlen(want_prefix), want_word) != NULL &&
           strchr(err.message, '\n') == NULL && memcmp(out, before, sizeof *out) == 0;
  if (!ok) printf("     wanted prefix \"%s\" and the word \"%s\"\n", want_prefix, want_word);
  check_report(ok, label, __FILE__, __LINE__);
  free(text);
  free(out);
  free(before);
}

/* A valid one-constituent file with one piece replaced by `piece`. */
#define AIR_PHASE "'phase': {'kind': 'rayleigh'}"
#define AIR_DENSITY "'density': [{'exp_term': 1, 'exp_scale_per_km': -0.125}]"
#define AIR(scat, abso, phase, density)                                                  \
  "{'name': 'air', 'scattering': " scat ", 'absorption': " abso ", " phase ", " density "}"
#define ATM(top, constituents)                                                           \
  "{'bottom_radius_km': 6360, 'top_radius_km': 6460, " top " 'constituents': [" constituents "]}"
#define GOOD_AIR AIR("[1e-3, 2e-3, 3e-3]", "[0, 0, 0]", AIR_PHASE, AIR_DENSITY)

static void test_default(void) {
  printf("\n-- built-in default (SPEC §4) --\n");
  sf_atmosphere *atm = calloc(1, sizeof *atm), *again = calloc(1, sizeof *again);
  sf_atmosphere_default(atm);
  CHECK(strcmp(atm->name, "earth-hillaire2020") == 0);
  CHECK_REL(atm->bottom_radius_km, 6360.0, 0.0);
  CHECK_REL(atm->top_radius_km, 6460.0, 0.0);
  CHECK(atm->n_channels == 3 && atm->spectral == 0);
  CHECK(strcmp(atm->channel_names[0], "r") == 0 && strcmp(atm->channel_names[1], "g") == 0 &&
        strcmp(atm->channel_names[2], "b") == 0);
  CHECK_REL(atm->sun_angular_radius_rad, 0.004675, 0.0);
  CHECK_REL(atm->sun_irradiance[2], 1.0, 0.0);
  CHECK_ABS(atm->ground_albedo[1], 0.0, 0.0);
  CHECK(atm->n_constituents == 3);
  int ray = sf_atmosphere_find(atm, "rayleigh"), mie = sf_atmosphere_find(atm, "mie"),
      oz = sf_atmosphere_find(atm, "ozone");
  CHECK(ray == 0 && mie == 1 && oz == 2);
  if (ray != 0 || mie != 1 || oz != 2) return;
  const sf_constituent *r = &atm->constituents[ray], *m = &atm->constituents[mie],
                       *o = &atm->constituents[oz];
  CHECK_REL(r->scattering[0], 5.802e-3, 0.0);
  CHECK_REL(r->scattering[1], 13.558e-3, 0.0);
  CHECK_REL(r->scattering[2], 33.1e-3, 0.0);
  CHECK(r->phase.kind == SF_PHASE_RAYLEIGH);
  CHECK_REL(m->scattering[1], 3.996e-3, 0.0);
  CHECK_REL(m->absorption[2], 0.444e-3, 0.0);
  CHECK(m->phase.kind == SF_PHASE_CORNETTE_SHANKS);
  CHECK_REL(m->phase.g, 0.8, 0.0);
  CHECK_REL(m->layers[0].exp_scale_per_km, -0.8333333, 0.0);
  CHECK_REL(o->absorption[0], 0.650e-3, 0.0);
  CHECK_REL(o->absorption[1], 1.881e-3, 0.0);
  CHECK_REL(o->absorption[2], 0.085e-3, 0.0);
  CHECK(o->phase.kind == SF_PHASE_NONE && o->n_layers == 2);
  CHECK_REL(o->layers[0].width_km, 25.0, 0.0);
  CHECK_REL(o->layers[1].constant, 2.6666667, 0.0);

  /* Densities against the closed forms of SPEC §4's layers. */
  CHECK_REL(sf_constituent_density(r, 8.0), exp(-1.0), 1e-15);
  CHECK_REL(sf_constituent_density(m, 1.2), exp(-0.8333333 * 1.2), 1e-15);
  double oz25 = sf_constituent_density(o, 25.0), oz10 = sf_constituent_density(o, 10.0);
  CHECK_ABS(oz25, 1.0, 1e-6);                          /* peak of the tent */
  CHECK_REL(oz25, -0.0666667 * 25.0 + 2.6666667, 1e-12); /* upper layer holds at 25 */
  CHECK_ABS(oz10, 0.0, 1e-6);                          /* foot of the tent */
  CHECK_ABS(oz10, 0.0666667 * 10.0 - 0.6666667, 1e-15);  /* 3e-7: the rounded SPEC numbers */
  CHECK_ABS(sf_constituent_density(o, 9.0), 0.0, 0.0);  /* clamped below the tent */
  CHECK_ABS(sf_constituent_density(o, 40.5), 0.0, 0.0); /* clamped above it */

  /* Loaded means finalized: the ozone layer boundary at 25 km is a kink. */
  int kink25 = 0;
  for (int i = 0; i < atm->n_kinks; ++i)
    if (fabs(atm->kink_altitudes_km[i] - 25.0) < 1e-9) kink25 = 1;
  printf("n_kinks %d, kink at 25 km: %d\n", atm->n_kinks, kink25);
  CHECK(kink25);

  /* The JSON text and the struct are the same thing. */
  sf_error err;
  sf_error_clear(&err);
  CHECK(sf_atmosphere_load_string(sf_atmosphere_default_json(), "default", again, &err) == 0);
  CHECK(memcmp(atm, again, sizeof *atm) == 0);

  /* Through a file on disk. */
  char path[] = "/tmp/skyfit_atm_XXXXXX";
  int fd = mkstemp(path);
  CHECK(fd >= 0);
  if (fd >= 0) {
    FILE *f = fdopen(fd, "w");
    fputs(sf_atmosphere_default_json(), f);
    fclose(f);
    memset(again, 0, sizeof *again);
    int rc = sf_atmosphere_load_file(path, again, &err);
    printf("load_file(%s) rc=%d %s\n", path, rc, err.message);
    CHECK(rc == 0 && memcmp(atm, again, sizeof *atm) == 0);
    remove(path);
  }
  free(atm);
  free(again);
}

static void test_minimal_defaults(void) {
  printf("\n-- optional keys take their documented defaults --\n");
  sf_atmosphere *atm = load_ok("minimal file",
      ATM("", GOOD_AIR ", {'name': 'o3', 'scattering': [0, 0, 0], 'absorption': 1e-3, "
                       "'density': [{'width_km': 20, 'constant': 0.5}, {'constant': 1}]}"));
  CHECK(strcmp(atm->name, "unnamed") == 0);
  CHECK(atm->n_channels == 3 && !atm->spectral);
  CHECK_REL(atm->sun_irradiance[0], 1.0, 0.0);
  CHECK_REL(atm->sun_irradiance[2], 1.0, 0.0);
  CHECK_ABS(atm->ground_albedo[2], 0.0, 0.0);
  CHECK_REL(atm->sun_angular_radius_rad, 0.004675, 0.0);
  CHECK(atm->constituents[1].phase.kind == SF_PHASE_NONE);
  CHECK_REL(atm->constituents[1].absorption[2], 1e-3, 0.0); /* one number: every channel */
  CHECK_REL(sf_constituent_density(&atm->constituents[1], 10.0), 0.5, 0.0);
  CHECK_REL(sf_constituent_density(&atm->constituents[1], 30.0), 1.0, 0.0);
  free(atm);

  atm = load_ok("scalar albedo, -0 coefficient",
      ATM("'ground_albedo': 0.3, 'sun_irradiance': [1.5, 2, 2.5],",
          AIR("[1e-3, 2e-3, 3e-3]", "[-0, 0, 0]", AIR_PHASE, AIR_DENSITY)));
  CHECK_REL(atm->ground_albedo[0], 0.3, 0.0);
  CHECK_REL(atm->ground_albedo[2], 0.3, 0.0);
  CHECK_REL(atm->sun_irradiance[1], 2.0, 0.0);
  CHECK(atm->constituents[0].absorption[0] == 0.0 && !signbit(atm->constituents[0].absorption[0]));
  free(atm);

  char name47[64], file[512];
  memset(name47, 'n', 47);
  name47[47] = '\0';
  snprintf(file, sizeof file, ATM("", "{'name': '%s', 'scattering': 0, 'absorption': 1, " AIR_DENSITY "}"),
           name47);
  atm = load_ok("47-character constituent name", file);
  CHECK(strcmp(atm->constituents[0].name, name47) == 0);
  free(atm);

  atm = load_ok("spectral channels",
      ATM("'channels': {'wavelengths_nm': [412.5, 550, 680]},",
          AIR("[1e-3, 2e-3, 3e-3]", "[0, 0, 0]", AIR_PHASE, AIR_DENSITY)));
  CHECK(atm->spectral == 1 && atm->n_channels == 3);
  CHECK(strcmp(atm->channel_names[0], "412.5") == 0 && strcmp(atm->channel_names[1], "550") == 0);
  CHECK_REL(atm->wavelengths_nm[2], 680.0, 0.0);
  free(atm);
}

static void test_base_default(void) {
  printf("\n-- \"base\": \"default\" merges by name --\n");
  sf_atmosphere *def = calloc(1, sizeof *def);
  sf_atmosphere_default(def);
  sf_atmosphere *atm = load_ok("override mie scattering",
      "{'base': 'default', 'constituents': [{'name': 'mie', 'scattering': [0.02, 0.02, 0.02]}]}");
  CHECK(atm->n_constituents == 3);
  CHECK(strcmp(atm->name, def->name) == 0);
  CHECK_REL(atm->bottom_radius_km, 6360.0, 0.0);
  const sf_constituent *m = &atm->constituents[1], *dm = &def->constituents[1];
  CHECK(strcmp(m->name, "mie") == 0);
  CHECK_REL(m->scattering[0], 0.02, 0.0);
  CHECK_REL(m->scattering[2], 0.02, 0.0);
  CHECK_REL(m->absorption[1], 0.444e-3, 0.0); /* not named: kept */
  CHECK(m->phase.kind == SF_PHASE_CORNETTE_SHANKS && m->phase.g == 0.8);
  CHECK(memcmp(m->layers, dm->layers, sizeof m->layers) == 0);
  CHECK(memcmp(&atm->constituents[0], &def->constituents[0], sizeof atm->constituents[0]) == 0);
  CHECK(memcmp(&atm->constituents[2], &def->constituents[2], sizeof atm->constituents[2]) == 0);
  free(atm);

  atm = load_ok("new constituent, top-level keys",
      "{'base': 'default', 'name': 'hazy', 'ground_albedo': 0.25, "
      "'constituents': [{'name': 'dust', 'scattering': 0.01, 'absorption': 0.002, "
      "'phase': {'kind': 'henyey_greenstein', 'g': 0.6}, 'density': [{'exp_term': 1, "
      "'exp_scale_per_km': -0.5}]}, {'name': 'ozone', 'absorption': [0, 0, 0]}]}");
  CHECK(atm->n_constituents == 4);
  CHECK(strcmp(atm->name, "hazy") == 0);
  CHECK_REL(atm->ground_albedo[1], 0.25, 0.0);
  CHECK_REL(atm->top_radius_km, 6460.0, 0.0);
  CHECK(strcmp(atm->constituents[3].name, "dust") == 0);
  CHECK_REL(atm->constituents[3].phase.g, 0.6, 0.0);
  CHECK_ABS(atm->constituents[2].absorption[1], 0.0, 0.0);
  CHECK(memcmp(atm->constituents[2].layers, def->constituents[2].layers, sizeof def->constituents[2].layers) == 0);
  free(atm);

  /* Replacing the channel set: the default's arrays that differ per RGB
   * channel do not apply to wavelengths (three wavelengths had taken the RGB
   * values silently, red's Rayleigh coefficient at 440 nm); those equal in
   * every channel carry over, as one number would. */
  expect_error("base: RGB Rayleigh vs three wavelengths",
               "{'base': 'default', 'channels': {'wavelengths_nm': [440, 550, 680]}}",
               "(base default) constituents[0].scattering", "per RGB channel");
  expect_error("base: RGB Rayleigh vs two wavelengths",
               "{'base': 'default', 'channels': {'wavelengths_nm': [450, 550]}}",
               "(base default) constituents[0].scattering", "per RGB channel");
  expect_error("base: overridden, inherited RGB key",
               "{'base': 'default', 'channels': {'wavelengths_nm': [450, 550]}, "
               "'constituents': [{'name': 'rayleigh', 'scattering': [1, 2], "
               "'absorption': 0}, {'name': 'mie', 'scattering': [1, 1]}]}",
               "(base default) constituents[2].absorption", "per RGB channel");
  atm = load_ok("grey default values at four wavelengths",
                "{'base': 'default', 'channels': {'wavelengths_nm': [400, 500, 600, 700]}, "
                "'constituents': [{'name': 'rayleigh', 'scattering': [4, 3, 2, 1]}, "
                "{'name': 'ozone', 'absorption': [0, 1e-3, 2e-3, 0]}]}");
  if (atm) {
    CHECK(atm->n_channels == 4);
    for (int ch = 0; ch < 4; ++ch) {
      CHECK(atm->ground_albedo[ch] == def->ground_albedo[0]);
      CHECK(atm->sun_irradiance[ch] == def->sun_irradiance[0]);
      CHECK(atm->constituents[1].scattering[ch] == def->constituents[1].scattering[0]);
      CHECK(atm->constituents[1].absorption[ch] == def->constituents[1].absorption[0]);
      CHECK(atm->constituents[2].scattering[ch] == 0.0);
      CHECK(atm->constituents[0].absorption[ch] == 0.0);
    }
    CHECK(atm->constituents[0].scattering[3] == 1.0 && atm->constituents[2].absorption[2] == 2e-3);
    free(atm);
  }
  /* "rgb" written out is the default's channel set: its arrays apply. */
  atm = load_ok("rgb written out", "{'base': 'default', 'channels': 'rgb'}");
  if (atm) {
    CHECK(atm->constituents[0].scattering[2] == def->constituents[0].scattering[2]);
    free(atm);
  }
  expect_error("base: bad override names user path",
               "{'base': 'default', 'constituents': [{'name': 'mie', 'phase': {'kind': "
               "'henyey_greenstein', 'g': 2}}]}",
               "constituents[0].phase.g", "< 1");
  expect_error("base: unknown key in override",
               "{'base': 'default', 'constituents': [{'name': 'ozone', 'absorbtion': 0}]}",
               "constituents[0].absorbtion", "unknown");
  expect_error("base: override without name",
               "{'base': 'default', 'constituents': [{'scattering': 0}]}",
               "constituents[0].name", "missing");
  expect_error("base: duplicate key in override",
               "{'base': 'default', 'constituents': [{'name': 'mie', 'scattering': 0, 'scattering': 1}]}",
               "constituents[0].scattering", "duplicate");
  expect_error("base: too many after merge",
               "{'base': 'default', 'constituents': [{'name': 'a', 'scattering': 0, 'absorption': 0, "
               "'density': [{}]}, {'name': 'b', 'scattering': 0, 'absorption': 0, 'density': [{}]}, "
               "{'name': 'c', 'scattering': 0, 'absorption': 0, 'density': [{}]}, {'name': 'd', "
               "'scattering': 0, 'absorption': 0, 'density': [{}]}, {'name': 'e', 'scattering': 0, "
               "'absorption': 0, 'density': [{}]}, {'name': 'f', 'scattering': 0, 'absorption': 0, "
               "'density': [{}]}]}",
               "constituents", "too many");
  expect_error("base: unknown base", "{'base': 'mars'}", "base", "unknown base");
  expect_error("base: not a string", "{'base': 1}", "base", "expected a string");
  free(def);
}

static int struct_round_trip(const char *label, const sf_atmosphere *atm) {
  char *first = sf_atmosphere_to_json(atm);
  CHECK(first != NULL);
  if (!first) return 0;
  sf_atmosphere *back = calloc(1, sizeof *back);
  sf_error err;
  sf_error_clear(&err);
  int rc = sf_atmosphere_load_string(first, "canonical", back, &err);
  printf("%s: canonical JSON %zu bytes, reload rc=%d %s\n", label, strlen(first), rc, err.message);
  CHECK(rc == 0);
  char *second = sf_atmosphere_to_json(back);
  CHECK(second && strcmp(first, second) == 0);
  CHECK(memcmp(atm, back, sizeof *atm) == 0);
  uint64_t h1 = sf_atmosphere_hash(atm), h2 = sf_atmosphere_hash(back);
  printf("%s: hash %016" PRIx64 " reloaded %016" PRIx64 "\n", label, h1, h2);
  CHECK(h1 == h2);
  /* The streaming hash equals FNV-1a of the text it would write. */
  CHECK(h1 == sf_fnv1a64(SF_FNV1A64_OFFSET, first, strlen(first)));
  CHECK(strstr(first, "\"base\"") == NULL);
  free(first);
  free(second);
  free(back);
  return 1;
}

static void test_canonical_and_hash(void) {
  printf("\n-- canonical JSON and hash --\n");
  /* Published FNV-1a 64 test vectors (Fowler/Noll/Vo reference suite). */
  CHECK(sf_fnv1a64(SF_FNV1A64_OFFSET, "", 0) == 0xcbf29ce484222325ULL);
  CHECK(sf_fnv1a64(SF_FNV1A64_OFFSET, "a", 1) == 0xaf63dc4c8601ec8cULL);
  CHECK(sf_fnv1a64(SF_FNV1A64_OFFSET, "foobar", 6) == 0x85944171f73967e8ULL);

  sf_atmosphere *def = calloc(1, sizeof *def);
  sf_atmosphere_default(def);
  struct_round_trip("default", def);
  char *text = sf_atmosphere_to_json(def);
  printf("%s", text);
  /* %.17g of 0.8, 0.004675, 5.802e-3 (printed by Python), every layer term explicit. */
  CHECK(strstr(text, "\"scattering\": [0.0058019999999999999, ") != NULL);
  CHECK(strstr(text, "\"g\": 0.80000000000000004") != NULL);
  CHECK(strstr(text, "\"sun_angular_radius_rad\": 0.0046750000000000003") != NULL);
  CHECK(strstr(text, "{\"width_km\": 25, \"exp_term\": 0, \"exp_scale_per_km\": 0, ") != NULL);
  free(text);

  sf_atmosphere *rich = load_ok("every feature",
      "{'name': 'odd \\'\\\\ name\\u0001', 'bottom_radius_km': 3389.5, 'top_radius_km': 3500, "
      "'channels': {'wavelengths_nm': [440, 550.25, 680]}, 'ground_albedo': 0.3, "
      "'sun_irradiance': [1.1, 1e-300, 3], 'sun_angular_radius_rad': 0.0031, 'constituents': ["
      "{'name': 'a', 'scattering': [1e-2, 2e-2, 3e-2], 'absorption': -0, 'phase': {'kind': "
      "'double_henyey_greenstein', 'g1': 0.85, 'g2': -0.3, 'f': 0.2}, 'density': [{'width_km': 5, "
      "'constant': 1}, {'width_km': 10, 'exp_term': 2, 'exp_scale_per_km': -0.1}, {'linear_per_km': "
      "-0.01, 'constant': 0.5}]}, {'name': 'b', 'scattering': 1, 'absorption': 0, 'phase': {'kind': "
      "'isotropic'}, 'density': [{'constant': 0.1}]}, {'name': 'c', 'scattering': 0.1, "
      "'absorption': 0, 'phase': {'kind': 'henyey_greenstein', 'g': -0.999}, 'density': [{}]}, "
      "{'name': 'd', 'scattering': 0, 'absorption': 0.1, 'density': [{'exp_term': 0.3, "
      "'exp_scale_per_km': 0.01}]}]}");
  CHECK(rich->constituents[0].phase.kind == SF_PHASE_DOUBLE_HENYEY_GREENSTEIN);
  CHECK_REL(rich->constituents[0].phase.f, 0.2, 0.0);
  CHECK(strcmp(rich->name, "odd \"\\ name\x01") == 0);
  struct_round_trip("every feature", rich);

  /* One coefficient changed by ~1e-15 relative must change the hash. */
  sf_atmosphere *near = malloc(sizeof *near);
  *near = *def;
  near->constituents[1].scattering[2] *= 1.0 + 1e-15;
  printf("scattering %.17g -> %.17g\n", def->constituents[1].scattering[2],
         near->constituents[1].scattering[2]);
  CHECK(near->constituents[1].scattering[2] != def->constituents[1].scattering[2]);
  char hex_def[17], hex_near[17], want[17];
  sf_atmosphere_hash_hex(def, hex_def);
  sf_atmosphere_hash_hex(near, hex_near);
  printf("hash default %s, perturbed %s\n", hex_def, hex_near);
  CHECK(strcmp(hex_def, hex_near) != 0);
  snprintf(want, sizeof want, "%016" PRIx64, sf_atmosphere_hash(def));
  CHECK(strlen(hex_def) == 16 && strspn(hex_def, "0123456789abcdef") == 16 && strcmp(hex_def, want) == 0);
  free(near);
  free(rich);
  free(def);
}

static void test_invalid_files(void) {
  printf("\n-- rejected files --\n");
  expect_error("syntax: missing comma",
               "{\n  'bottom_radius_km': 6360,\n  'top_radius_km': 6460\n  'constituents': []\n}",
               "line 4, column 3", "syntax");
  expect_error("syntax: end of input", "{\n  'constituents': [1,\n", "line 3, column 1", "end of input");
  expect_error("syntax: trailing text", "{}\n{}", "line 2, column 1", "syntax");
  expect_error("root not an object", "[1, 2]", "(root)", "object");

  expect_error("unknown key: top level", ATM("'colour': 1,", GOOD_AIR), "colour", "unknown");
  expect_error("unknown key: constituent",
               ATM("", "{'name': 'air', 'scatering': 0, 'absorption': 0, " AIR_DENSITY "}"),
               "constituents[0].scatering", "unknown");
  expect_error("unknown key: phase",
               ATM("", AIR("0.1", "0", "'phase': {'kind': 'rayleigh', 'g': 0.5}", AIR_DENSITY)),
               "constituents[0].phase.g", "unknown");
  expect_error("unknown key: layer",
               ATM("", AIR("0.1", "0", AIR_PHASE, "'density': [{'exp_scale': 1}]")),
               "constituents[0].density[0].exp_scale", "unknown");
  expect_error("unknown key: channels", ATM("'channels': {'wavelength_nm': [550]},", GOOD_AIR),
               "channels.wavelength_nm", "unknown");
  expect_error("duplicate key", ATM("'top_radius_km': 6500,", GOOD_AIR), "top_radius_km", "duplicate");

  expect_error("type: radius string",
               "{'bottom_radius_km': '6360', 'top_radius_km': 6460, 'constituents': [" GOOD_AIR "]}",
               "bottom_radius_km", "expected a number");
  expect_error("type: scattering string", ATM("", AIR("'abc'", "0", AIR_PHASE, AIR_DENSITY)),
               "constituents[0].scattering", "got a string");
  expect_error("type: scattering element", ATM("", AIR("[0.1, true, 0.3]", "0", AIR_PHASE, AIR_DENSITY)),
               "constituents[0].scattering[1]", "got a boolean");
  expect_error("type: phase kind", ATM("", AIR("0.1", "0", "'phase': {'kind': 3}", AIR_DENSITY)),
               "constituents[0].phase.kind", "expected a string");
  expect_error("type: density object", ATM("", AIR("0.1", "0", AIR_PHASE, "'density': {}")),
               "constituents[0].density", "expected an array");
  expect_error("type: name number", ATM("", "{'name': 7, 'scattering': 0, 'absorption': 0, " AIR_DENSITY "}"),
               "constituents[0].name", "expected a string");
  expect_error("type: channels number", ATM("'channels': 3,", GOOD_AIR), "channels", "expected");
  expect_error("type: constituent", ATM("", "3"), "constituents[0]", "expected an object");
  expect_error("type: layer", ATM("", AIR("0.1", "0", AIR_PHASE, "'density': [null]")),
               "constituents[0].density[0]", "expected an object");

  expect_error("missing: bottom radius", "{'top_radius_km': 6460, 'constituents': [" GOOD_AIR "]}",
               "bottom_radius_km", "missing");
  expect_error("missing: top radius", "{'bottom_radius_km': 6360, 'constituents': [" GOOD_AIR "]}",
               "top_radius_km", "missing");
  expect_error("missing: constituents", "{'bottom_radius_km': 6360, 'top_radius_km': 6460}",
               "constituents", "missing");
  expect_error("missing: constituent name", ATM("", "{'scattering': 0, 'absorption': 0, " AIR_DENSITY "}"),
               "constituents[0].name", "missing");
  expect_error("missing: scattering", ATM("", "{'name': 'x', 'absorption': 0, " AIR_DENSITY "}"),
               "constituents[0].scattering", "missing");
  expect_error("missing: absorption", ATM("", "{'name': 'x', 'scattering': 0, " AIR_DENSITY "}"),
               "constituents[0].absorption", "missing");
  expect_error("missing: density", ATM("", "{'name': 'x', 'scattering': 0, 'absorption': 0}"),
               "constituents[0].density", "missing");
  expect_error("missing: phase of a scatterer",
               ATM("", "{'name': 'x', 'scattering': [0, 0.1, 0], 'absorption': 0, " AIR_DENSITY "}"),
               "constituents[0].phase", "missing");
  expect_error("missing: phase kind", ATM("", AIR("0.1", "0", "'phase': {}", AIR_DENSITY)),
               "constituents[0].phase.kind", "missing");
  expect_error("missing: g", ATM("", AIR("0.1", "0", "'phase': {'kind': 'cornette_shanks'}", AIR_DENSITY)),
               "constituents[0].phase.g", "missing");
  expect_error("missing: f",
               ATM("", AIR("0.1", "0", "'phase': {'kind': 'double_henyey_greenstein', 'g1': 0.5, 'g2': 0}",
                           AIR_DENSITY)),
               "constituents[0].phase.f", "missing");

  expect_error("non-finite: scattering", ATM("", AIR("[0.1, 1e999, 0.3]", "0", AIR_PHASE, AIR_DENSITY)),
               "constituents[0].scattering[1]", "finite");
  expect_error("non-finite: irradiance", ATM("'sun_irradiance': [-1e999, 1, 1],", GOOD_AIR),
               "sun_irradiance[0]", "finite");
  expect_error("non-finite: radius",
               "{'bottom_radius_km': 6360, 'top_radius_km': 1e400, 'constituents': [" GOOD_AIR "]}",
               "top_radius_km", "finite");
  expect_error("non-finite: albedo", ATM("'ground_albedo': 1e999,", GOOD_AIR), "ground_albedo", "finite");
  expect_error("non-finite: layer term",
               ATM("", AIR("0.1", "0", AIR_PHASE, "'density': [{'exp_term': 1e999}]")),
               "constituents[0].density[0].exp_term", "finite");
  expect_error("non-finite: g",
               ATM("", AIR("0.1", "0", "'phase': {'kind': 'henyey_greenstein', 'g': -1e999}", AIR_DENSITY)),
               "constituents[0].phase.g", "finite");

  expect_error("negative: absorption", ATM("", AIR("0.1", "[0, 0, -1e-3]", AIR_PHASE, AIR_DENSITY)),
               "constituents[0].absorption[2]", "negative");
  expect_error("negative: scattering", ATM("", AIR("-0.1", "0", AIR_PHASE, AIR_DENSITY)),
               "constituents[0].scattering", "negative");
  expect_error("negative: albedo", ATM("'ground_albedo': [0.1, -0.1, 0.1],", GOOD_AIR),
               "ground_albedo[1]", "negative");
  expect_error("negative: irradiance", ATM("'sun_irradiance': -2,", GOOD_AIR), "sun_irradiance", "negative");
  expect_error("negative: sun radius", ATM("'sun_angular_radius_rad': -0.01,", GOOD_AIR),
               "sun_angular_radius_rad", "[0, pi/2)");

  expect_error("length: absorption", ATM("", AIR("0.1", "[0, 0]", AIR_PHASE, AIR_DENSITY)),
               "constituents[0].absorption", "expected 3 values");
  expect_error("length: albedo", ATM("'ground_albedo': [0, 0, 0, 0],", GOOD_AIR), "ground_albedo",
               "expected 3 values");
  expect_error("length: spectral scattering",
               ATM("'channels': {'wavelengths_nm': [450, 550]},", GOOD_AIR),
               "constituents[0].scattering", "expected 2 values");

  expect_error("radii: top == bottom",
               "{'bottom_radius_km': 6360, 'top_radius_km': 6360, 'constituents': [" GOOD_AIR "]}",
               "top_radius_km", "greater");
  expect_error("radii: top < bottom",
               "{'bottom_radius_km': 6360, 'top_radius_km': 6000, 'constituents': [" GOOD_AIR "]}",
               "top_radius_km", "greater");
  expect_error("radii: zero bottom",
               "{'bottom_radius_km': 0, 'top_radius_km': 6460, 'constituents': [" GOOD_AIR "]}",
               "bottom_radius_km", "positive");
  expect_error("radii: negative bottom",
               "{'bottom_radius_km': -1, 'top_radius_km': 6460, 'constituents': [" GOOD_AIR "]}",
               "bottom_radius_km", "positive");

  expect_error("|g| = 1, second constituent",
               ATM("", GOOD_AIR ", {'name': 'mie', 'scattering': 0.004, 'absorption': 0, "
                   "'phase': {'kind': 'cornette_shanks', 'g': 1}, " AIR_DENSITY "}"),
               "constituents[1].phase.g", "< 1");
  expect_error("|g1| > 1",
               ATM("", AIR("0.1", "0", "'phase': {'kind': 'double_henyey_greenstein', 'g1': -1.2, "
                           "'g2': 0, 'f': 0.5}", AIR_DENSITY)),
               "constituents[0].phase.g1", "< 1");
  expect_error("|g2| = 1",
               ATM("", AIR("0.1", "0", "'phase': {'kind': 'double_henyey_greenstein', 'g1': 0.2, "
                           "'g2': 1, 'f': 0.5}", AIR_DENSITY)),
               "constituents[0].phase.g2", "< 1");
  expect_error("f > 1",
               ATM("", AIR("0.1", "0", "'phase': {'kind': 'double_henyey_greenstein', 'g1': 0.2, "
                           "'g2': 0.1, 'f': 1.5}", AIR_DENSITY)),
               "constituents[0].phase.f", "[0, 1]");
  expect_error("unknown phase kind", ATM("", AIR("0.1", "0", "'phase': {'kind': 'mie'}", AIR_DENSITY)),
               "constituents[0].phase.kind", "unknown phase kind");

  expect_error("empty constituents", ATM("", ""), "constituents", "empty");
#define NC(n) "{'name': '" n "', 'scattering': 0, 'absorption': 0, 'density': [{}]}"
  expect_error("too many constituents",
               ATM("", NC("a") "," NC("b") "," NC("c") "," NC("d") "," NC("e") "," NC("f") "," NC("g")
                   "," NC("h") "," NC("i")),
               "constituents", "too many");
  expect_error("too many layers",
               ATM("", AIR("0.1", "0", AIR_PHASE, "'density': [{'width_km': 1}, {'width_km': 1}, "
                           "{'width_km': 1}, {'width_km': 1}, {'width_km': 1}, {'width_km': 1}, "
                           "{'width_km': 1}, {'width_km': 1}, {}]")),
               "constituents[0].density", "too many");
  expect_error("no layers", ATM("", AIR("0.1", "0", AIR_PHASE, "'density': []")),
               "constituents[0].density", "empty");
  expect_error("zero-width inner layer",
               ATM("", AIR("0.1", "0", AIR_PHASE, "'density': [{'width_km': 0, 'constant': 1}, {}]")),
               "constituents[0].density[0].width_km", "width");
  expect_error("negative-width inner layer",
               ATM("", AIR("0.1", "0", AIR_PHASE, "'density': [{'width_km': 2}, {'width_km': -3}, {}]")),
               "constituents[0].density[1].width_km", "width");
  expect_error("duplicate constituent names", ATM("", NC("a") "," NC("b") "," NC("a")),
               "constituents[2].name", "duplicate");
  expect_error("empty constituent name", ATM("", NC("")), "constituents[0].name", "empty");
  /* a name heads CSV columns (skyfit eval): no comma, quote or control character */
  expect_error("comma in a constituent name", ATM("", NC("a,b")), "constituents[0].name", "letters, digits");
  expect_error("quote in a constituent name", ATM("", NC("a\\\"b")), "constituents[0].name", "letters, digits");
  expect_error("comma in a merged name", "{'base': 'default', 'constituents': [{'name': 'dust,2', 'base': 'mie'}]}",
               "constituents[0].name", "letters, digits");
  /* it names a table's file: a path had been refused only later, without
   * the file or the key */
  expect_error("path in a constituent name", ATM("", NC("../x")), "constituents[0].name", "letters, digits");
  expect_error("space in a constituent name", ATM("", NC("dust 2")), "constituents[0].name", "letters, digits");
  expect_error("input column as a constituent name", ATM("", NC("mu")), "constituents[0].name", "input columns");
  expect_error("input column over base",
               "{'base': 'default', 'constituents': [{'name': 'h_km', 'scattering': 0, 'absorption': 1e-3, "
               "'density': [{'constant': 1}]}]}",
               "constituents[0].name", "input columns");
  expect_error("top radius beyond 1e12 km", "{'base': 'default', 'top_radius_km': 1e308}", "top_radius_km", "at most");
  expect_error("ground albedo above 1", "{'base': 'default', 'ground_albedo': [0.1, 1.5, 0.1]}", "ground_albedo",
               "at most 1");
  /* over base "default" an empty list would merge nothing */
  expect_error("empty constituents over base", "{'base': 'default', 'constituents': []}", "constituents", "empty");
  expect_error("constituent name too long", ATM("", NC("abcdefghijklmnopqrstuvwxyzabcdefghijklmnopqrstuv")),
               "constituents[0].name", "too long");
  char long_name[160], file[1024];
  memset(long_name, 'x', 96);
  long_name[96] = '\0';
  snprintf(file, sizeof file, ATM("'name': '%s',", GOOD_AIR), long_name);
  expect_error("atmosphere name too long", file, "name", "too long");

  expect_error("channels: unknown set", ATM("'channels': 'xyz',", GOOD_AIR), "channels", "unknown channel set");
  expect_error("channels: not increasing", ATM("'channels': {'wavelengths_nm': [550, 450, 700]},", GOOD_AIR),
               "channels.wavelengths_nm[1]", "increasing");
  expect_error("channels: negative wavelength", ATM("'channels': {'wavelengths_nm': [-550, 450, 700]},", GOOD_AIR),
               "channels.wavelengths_nm[0]", "positive");
  expect_error("channels: empty", ATM("'channels': {'wavelengths_nm': []},", GOOD_AIR),
               "channels.wavelengths_nm", "empty");
  expect_error("channels: same printed name",
               ATM("'channels': {'wavelengths_nm': [550, 550.0000001, 700]},", GOOD_AIR),
               "channels.wavelengths_nm[1]", "same channel name");
  char many[4096] = "'channels': {'wavelengths_nm': [";
  for (int i = 0; i <= SF_MAX_CHANNELS; ++i)
    snprintf(many + strlen(many), sizeof many - strlen(many), "%s%d", i ? ", " : "", 400 + i);
  strcat(many, "]},");
  char big[8192];
  snprintf(big, sizeof big, ATM("%s", GOOD_AIR), many);
  expect_error("channels: too many wavelengths", big, "channels.wavelengths_nm", "too many");
}

static void test_file_errors(void) {
  printf("\n-- file errors --\n");
  sf_atmosphere *out = calloc(1, sizeof *out);
  sf_error err;
  sf_error_clear(&err);
  const char *missing = "/nonexistent-dir/skyfit-atmosphere.json";
  int rc = sf_atmosphere_load_file(missing, out, &err);
  printf("missing file rc=%d %s\n", rc, err.message);
  CHECK(rc == SF_ERR_INPUT && strncmp(err.message, missing, strlen(missing)) == 0 &&
        strstr(err.message, "No such file") != NULL);

  char path[] = "/tmp/skyfit_atm_XXXXXX";
  int fd = mkstemp(path);
  CHECK(fd >= 0);
  if (fd >= 0) {
    FILE *f = fdopen(fd, "w");
    fputs("{\n  \"bottom_radius_km\": 6360,\n  \"top_radius_km\": 6460,\n  \"oops\": 1\n}\n", f);
    fclose(f);
    sf_error_clear(&err);
    rc = sf_atmosphere_load_file(path, out, &err);
    printf("file with unknown key rc=%d %s\n", rc, err.message);
    char want[256];
    snprintf(want, sizeof want, "%s: oops: unknown key", path);
    CHECK(rc == SF_ERR_INPUT && strncmp(err.message, want, strlen(want)) == 0);

    f = fopen(path, "wb");
    fwrite("{\"name\": \"a\0b\"}", 1, 15, f);
    fclose(f);
    sf_error_clear(&err);
    rc = sf_atmosphere_load_file(path, out, &err);
    printf("file with NUL byte rc=%d %s\n", rc, err.message);
    CHECK(rc == SF_ERR_INPUT && strstr(err.message, "NUL byte") != NULL);
    remove(path);
  }
  free(out);
}

int main(void) {
  test_default();
  test_minimal_defaults();
  test_base_default();
  test_canonical_and_hash();
  test_invalid_files();
  test_file_errors();
  return check_summary();
}
