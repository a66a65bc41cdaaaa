/* Table cache (SPEC §6): keys are FNV-1a 64 (checked against the published
 * test vectors) of everything that determines a table, so changing any one
 * input changes the key; a stored table loads back bit-identical; a missing
 * file is a plain miss; a damaged or mislabelled file is reported as
 * corrupt and treated as a miss, and storing again repairs it. */
#include <dirent.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "data/table.h"
#include "data/table_cache.h"
#include "tests/check.h"
#include "util/hash64.h"

static const char *const atmosphere_json =
    "{\"name\":\"earth\",\"bottom_radius_km\":6360,\"top_radius_km\":6420,\"channels\":\"rgb\"}";

static sf_table_desc transmittance_desc(void) {
  sf_table_desc d;
  memset(&d, 0, sizeof d);
  strcpy(d.quantity, "transmittance");
  strcpy(d.parameterization, "bruneton");
  d.n_axes = 2;
  strcpy(d.axes[0].name, "mu");
  strcpy(d.axes[0].mapping, "bruneton_mu");
  d.axes[0].size = 64;
  d.axes[0].min = -1.0;
  d.axes[0].max = 1.0;
  strcpy(d.axes[1].name, "r_km");
  strcpy(d.axes[1].mapping, "bruneton_r");
  d.axes[1].size = 16;
  d.axes[1].min = 6360.0;
  d.axes[1].max = 6420.0;
  d.n_channels = 3;
  strcpy(d.channel_names[0], "r");
  strcpy(d.channel_names[1], "g");
  strcpy(d.channel_names[2], "b");
  return d;
}

/* A transmittance-like analytic table: exp(-k_c * (1 + i1) / (1.1 + mu)). */
static float value_at(int i0, int i1, int c) {
  double mu = -1.0 + 2.0 * i0 / 63.0;
  return (float)exp(-(0.1 + 0.2 * c) * (1 + i1) / (1.1 + mu));
}

static void fill(sf_table *t) {
  for (int i1 = 0; i1 < 16; ++i1)
    for (int i0 = 0; i0 < 64; ++i0)
      for (int c = 0; c < 3; ++c) t->data[c + 3 * (i0 + 64 * i1)] = value_at(i0, i1, c);
}

static long wrong_values(const sf_table *t) {
  long wrong = 0;
  for (int i1 = 0; i1 < 16; ++i1)
    for (int i0 = 0; i0 < 64; ++i0)
      for (int c = 0; c < 3; ++c) {
        float want = value_at(i0, i1, c);
        if (memcmp(&want, &t->data[c + 3 * (i0 + 64 * i1)], 4) != 0) ++wrong;
      }
  return wrong;
}

static char work_dir[256];

static void fnv_vectors(void) {
  /* Published FNV-1a 64 test vectors (Noll's fnv test suite). */
  char hex[17];
  sf_hash64_hex(sf_fnv1a64(SF_FNV1A64_OFFSET, "", 0), hex);
  printf("fnv1a64(\"\") = %s\n", hex);
  CHECK(strcmp(hex, "cbf29ce484222325") == 0);
  sf_hash64_hex(sf_fnv1a64(SF_FNV1A64_OFFSET, "a", 1), hex);
  printf("fnv1a64(\"a\") = %s\n", hex);
  CHECK(strcmp(hex, "af63dc4c8601ec8c") == 0);
  sf_hash64_hex(sf_fnv1a64(SF_FNV1A64_OFFSET, "foobar", 6), hex);
  printf("fnv1a64(\"foobar\") = %s\n", hex);
  CHECK(strcmp(hex, "85944171f73967e8") == 0);
}

static void keys(void) {
  printf("-- keys\n");
  sf_table_desc base = transmittance_desc();
  char keys[16][17];
  const char *what[16];
  int n = 0;
  sf_table_cache_key(&base, atmosphere_json, 4, "skyfit 0.1.0", keys[n]);
  what[n++] = "base";
  char again[17];
  sf_table_cache_key(&base, atmosphere_json, 4, "skyfit 0.1.0", again);
  CHECK(strcmp(again, keys[0]) == 0);
  /* The stored hash is not an input: a desc carrying its key has the same key. */
  sf_table_desc with_hash = base;
  strcpy(with_hash.content_hash, keys[0]);
  sf_table_cache_key(&with_hash, atmosphere_json, 4, "skyfit 0.1.0", again);
  CHECK(strcmp(again, keys[0]) == 0);

  char json_changed[256];
  strcpy(json_changed, atmosphere_json);
  json_changed[strlen(json_changed) - 3] = 'x';   /* "rgb" -> "rxb" */
  sf_table_desc d;
  sf_table_cache_key(&base, json_changed, 4, "skyfit 0.1.0", keys[n]); what[n++] = "atmosphere JSON, one char";
  sf_table_cache_key(&base, atmosphere_json, 5, "skyfit 0.1.0", keys[n]); what[n++] = "scattering orders 4 -> 5";
  sf_table_cache_key(&base, atmosphere_json, 4, "skyfit 0.1.1", keys[n]); what[n++] = "code version";
  d = base; strcpy(d.quantity, "transmittancf");
  sf_table_cache_key(&d, atmosphere_json, 4, "skyfit 0.1.0", keys[n]); what[n++] = "quantity";
  d = base; strcpy(d.parameterization, "leenman");
  sf_table_cache_key(&d, atmosphere_json, 4, "skyfit 0.1.0", keys[n]); what[n++] = "parameterization";
  d = base; d.axes[0].size = 65;
  sf_table_cache_key(&d, atmosphere_json, 4, "skyfit 0.1.0", keys[n]); what[n++] = "axis 0 size";
  d = base; d.axes[1].max = nextafter(6420.0, 7000.0);
  sf_table_cache_key(&d, atmosphere_json, 4, "skyfit 0.1.0", keys[n]); what[n++] = "axis 1 max + 1 ulp";
  d = base; d.axes[0].min = nextafter(-1.0, 0.0);
  sf_table_cache_key(&d, atmosphere_json, 4, "skyfit 0.1.0", keys[n]); what[n++] = "axis 0 min + 1 ulp";
  d = base; strcpy(d.axes[1].mapping, "leenman_x");
  sf_table_cache_key(&d, atmosphere_json, 4, "skyfit 0.1.0", keys[n]); what[n++] = "axis 1 mapping";
  d = base; strcpy(d.axes[0].name, "nu");
  sf_table_cache_key(&d, atmosphere_json, 4, "skyfit 0.1.0", keys[n]); what[n++] = "axis 0 name";
  d = base; strcpy(d.channel_names[2], "c");
  sf_table_cache_key(&d, atmosphere_json, 4, "skyfit 0.1.0", keys[n]); what[n++] = "channel name";
  d = base; d.n_channels = 2;
  sf_table_cache_key(&d, atmosphere_json, 4, "skyfit 0.1.0", keys[n]); what[n++] = "channel count";
  /* Field boundaries matter: "ab"+"c" must differ from "a"+"bc". */
  d = base; strcpy(d.quantity, "transmittanc"); strcpy(d.parameterization, "ebruneton");
  sf_table_cache_key(&d, atmosphere_json, 4, "skyfit 0.1.0", keys[n]); what[n++] = "boundary shifted";
  int collisions = 0, malformed = 0;
  for (int i = 0; i < n; ++i) {
    printf("%-28s %s\n", what[i], keys[i]);
    malformed += strlen(keys[i]) != 16 || strspn(keys[i], "0123456789abcdef") != 16;
    for (int j = 0; j < i; ++j) collisions += strcmp(keys[i], keys[j]) == 0;
  }
  printf("%d keys, %d equal pairs, %d malformed\n", n, collisions, malformed);
  CHECK(collisions == 0 && malformed == 0);
}

static void paths(void) {
  printf("-- paths\n");
  char out[4096], want[4096];
  sf_error err = {0};
  CHECK(sf_table_cache_path("/some/cache", "single_mie", "0123456789abcdef", out, sizeof out, &err) == SF_OK);
  snprintf(want, sizeof want, "%s", "/some/cache/single_mie-0123456789abcdef.exr");
  printf("path: %s\n", out);
  CHECK(strcmp(out, want) == 0);
  err = (sf_error){0};
  CHECK(sf_table_cache_path("/c", "../etc", "0123456789abcdef", out, sizeof out, &err) == SF_ERR_INPUT);
  printf("bad quantity: %s\n", err.message);
  err = (sf_error){0};
  CHECK(sf_table_cache_path("/c", "single_mie", "0123", out, sizeof out, &err) == SF_ERR_INPUT);
  printf("bad key: %s\n", err.message);
  err = (sf_error){0};
  CHECK(sf_table_cache_path("/a/long/folder", "single_mie", "0123456789abcdef", out, 20, &err) == SF_ERR_INPUT);
  printf("too long: %s\n", err.message);
}

static void corrupt_file(const char *path, long offset_from_end, unsigned char mask) {
  FILE *f = fopen(path, "r+b");
  fseek(f, -offset_from_end, SEEK_END);
  int c = fgetc(f);
  fseek(f, -offset_from_end, SEEK_END);
  fputc(c ^ mask, f);
  fclose(f);
}

static void store_and_load(void) {
  printf("-- store, load, corruption\n");
  char dir[512];
  snprintf(dir, sizeof dir, "%s/nested/cache", work_dir);   /* created by store */
  sf_table_desc desc = transmittance_desc();
  sf_table_cache_key(&desc, atmosphere_json, 0, "skyfit test", desc.content_hash);
  char path[4096];
  sf_error err = {0};
  sf_table_cache_path(dir, desc.quantity, desc.content_hash, path, sizeof path, &err);

  sf_table loaded;
  sf_error problem = {0};
  CHECK(sf_table_cache_load(dir, &desc, 0, &loaded, &problem) == 0 && problem.status == SF_OK &&
        loaded.data == NULL);
  printf("empty cache: miss, problem status %d\n", problem.status);

  sf_table t;
  CHECK(sf_table_init(&t, &desc, atmosphere_json, 0, &err) == SF_OK);
  fill(&t);
  CHECK(sf_table_cache_store(dir, &t, &err) == SF_OK);
  if (err.status) printf("store: %s\n", err.message);
  struct stat st;
  CHECK(stat(path, &st) == 0 && S_ISREG(st.st_mode));
  printf("stored %s (%lld bytes)\n", path, (long long)st.st_size);

  problem = (sf_error){0};
  CHECK(sf_table_cache_load(dir, &desc, 0, &loaded, &problem) == 1 && problem.status == SF_OK);
  long wrong = loaded.data ? wrong_values(&loaded) : -1;
  printf("hit: %ld of %d values differ in bits\n", wrong, 64 * 16 * 3);
  CHECK(wrong == 0);
  CHECK(loaded.data && strcmp(loaded.desc.content_hash, desc.content_hash) == 0 &&
        strcmp(loaded.desc.quantity, "transmittance") == 0 && loaded.desc.axes[1].max == 6420.0 &&
        loaded.desc.axes[0].size == 64 && strcmp(loaded.desc.channel_names[1], "g") == 0 &&
        strcmp(loaded.atmosphere_json, atmosphere_json) == 0);
  sf_table_free(&loaded);

  /* Another key (another atmosphere) is a miss, not a corrupt file. */
  sf_table_desc other = desc;
  sf_table_cache_key(&other, "{\"name\":\"mars\"}", 0, "skyfit test", other.content_hash);
  problem = (sf_error){0};
  CHECK(sf_table_cache_load(dir, &other, 0, &loaded, &problem) == 0 && problem.status == SF_OK);

  /* Damage inside the pixel data: reported, treated as absent. */
  corrupt_file(path, 100, 0x04);
  problem = (sf_error){0};
  CHECK(sf_table_cache_load(dir, &desc, 0, &loaded, &problem) == 0 && loaded.data == NULL);
  char prefix[4200];
  snprintf(prefix, sizeof prefix, "cache file %s is corrupt: ", path);
  CHECK(problem.status == SF_ERR_INPUT && strncmp(problem.message, prefix, strlen(prefix)) == 0);
  printf("flipped byte: %s\n", problem.message);

  /* Recompute and store again: the cache is repaired. */
  err = (sf_error){0};
  CHECK(sf_table_cache_store(dir, &t, &err) == SF_OK);
  problem = (sf_error){0};
  CHECK(sf_table_cache_load(dir, &desc, 0, &loaded, &problem) == 1 && problem.status == SF_OK);
  sf_table_free(&loaded);

  /* Truncated and empty files. */
  CHECK(truncate(path, st.st_size / 2) == 0);
  problem = (sf_error){0};
  CHECK(sf_table_cache_load(dir, &desc, 0, &loaded, &problem) == 0 && problem.status == SF_ERR_INPUT &&
        strncmp(problem.message, prefix, strlen(prefix)) == 0);
  printf("truncated: %s\n", problem.message);
  CHECK(truncate(path, 0) == 0);
  problem = (sf_error){0};
  CHECK(sf_table_cache_load(dir, &desc, 0, &loaded, &problem) == 0 && problem.status == SF_ERR_INPUT);
  printf("empty: %s\n", problem.message);

  /* A valid table file under another table's name. */
  err = (sf_error){0};
  CHECK(sf_table_cache_store(dir, &t, &err) == SF_OK);
  char other_path[4096];
  sf_table_cache_path(dir, other.quantity, other.content_hash, other_path, sizeof other_path, &err);
  CHECK(rename(path, other_path) == 0);
  problem = (sf_error){0};
  CHECK(sf_table_cache_load(dir, &other, 0, &loaded, &problem) == 0 && problem.status == SF_ERR_INPUT &&
        strstr(problem.message, "different table"));
  printf("mislabelled: %s\n", problem.message);
  remove(other_path);

  /* A folder that cannot be made. */
  char blocked[600];
  snprintf(blocked, sizeof blocked, "%s/file", work_dir);
  FILE *f = fopen(blocked, "w");
  fclose(f);
  char under_file[700];
  snprintf(under_file, sizeof under_file, "%s/cache", blocked);
  err = (sf_error){0};
  CHECK(sf_table_cache_store(under_file, &t, &err) == SF_ERR_INPUT);
  printf("folder under a file: %s\n", err.message);
  remove(blocked);
  sf_table_free(&t);

  /* Tidy up: nothing but our folders should be left. */
  CHECK(rmdir(dir) == 0);
  snprintf(dir, sizeof dir, "%s/nested", work_dir);
  CHECK(rmdir(dir) == 0);
}

static void channels_from_atmosphere(void) {
  sf_atmosphere *atm = calloc(1, sizeof *atm);
  static const char *const names[4] = {"440", "550", "610", "680"};
  atm->n_channels = 4;
  atm->spectral = 1;
  for (int c = 0; c < 4; ++c) strcpy(atm->channel_names[c], names[c]);
  sf_table_desc d = transmittance_desc();
  sf_table_desc_set_channels(&d, atm);
  int same = d.n_channels == 4;
  for (int c = 0; same && c < 4; ++c) same = strcmp(d.channel_names[c], names[c]) == 0;
  printf("channels from a 4-wavelength atmosphere: %d (%s ... %s)\n", d.n_channels, d.channel_names[0],
         d.channel_names[3]);
  CHECK(same);
  free(atm);
}

int main(void) {
  const char *tmp = getenv("TMPDIR");
  snprintf(work_dir, sizeof work_dir, "%s/skyfit_table_cache_XXXXXX", tmp && *tmp ? tmp : "/tmp");
  if (!mkdtemp(work_dir)) { perror("mkdtemp"); return 1; }
  fnv_vectors();
  channels_from_atmosphere();
  keys();
  paths();
  store_and_load();
  CHECK(rmdir(work_dir) == 0);
  return check_summary();
}
