#include "data/table_cache.h"

#include <errno.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>

#include "data/table_exr.h"
#include "util/cache_prune.h"
#include "util/hash64.h"
#include "util/make_folders.h"

/* Bump when the key's recipe changes, so old files are simply not found. */
#define CACHE_KEY_RECIPE "skyfit-table-key 1"

static uint64_t hash_text(uint64_t h, const char *s) { return sf_fnv1a64_field(h, s ? s : ""); }

static uint64_t hash_number(uint64_t h, double v) {
  char text[40];
  snprintf(text, sizeof text, "%.17g", v);
  return sf_fnv1a64_field(h, text);
}

void sf_table_cache_key(const sf_table_desc *desc, const char *atmosphere_json, int scattering_orders,
                        const char *code_version, char key[17]) {
  /* Every field goes in length-prefixed, so no two different inputs give
   * the same byte stream. */
  uint64_t h = hash_text(SF_FNV1A64_OFFSET, CACHE_KEY_RECIPE);
  h = hash_text(h, code_version);
  h = hash_text(h, atmosphere_json);
  h = hash_text(h, desc->quantity);
  h = hash_text(h, desc->parameterization);
  h = hash_number(h, desc->n_axes);
  for (int k = 0; k < desc->n_axes && k < SF_TABLE_MAX_AXES; ++k) {
    const sf_table_axis *a = &desc->axes[k];
    h = hash_text(h, a->name);
    h = hash_number(h, a->size);
    h = hash_number(h, a->min);
    h = hash_number(h, a->max);
    h = hash_text(h, a->mapping);
  }
  h = hash_number(h, desc->n_channels);
  for (int c = 0; c < desc->n_channels && c < SF_MAX_CHANNELS; ++c) h = hash_text(h, desc->channel_names[c]);
  h = hash_number(h, scattering_orders);
  sf_hash64_hex(sf_hash64_mix(h), key);
}

static int safe_name(const char *s) {
  if (!s || !*s) return 0;
  for (; *s; ++s) {
    char c = *s;
    if (!((c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' ||
          c == '-' || c == '.'))
      return 0;
  }
  return 1;
}

static int hex16(const char *s) {
  if (!s || strlen(s) != 16) return 0;
  for (; *s; ++s)
    if (!((*s >= '0' && *s <= '9') || (*s >= 'a' && *s <= 'f'))) return 0;
  return 1;
}

int sf_table_cache_path(const char *dir, const char *quantity, const char *key, char *out, size_t n,
                        sf_error *err) {
  if (!safe_name(quantity) || quantity[0] == '.')
    return sf_fail(err, SF_ERR_INPUT, "table cache: quantity '%s' is not a safe file name part",
                   quantity ? quantity : "");
  if (!hex16(key))
    return sf_fail(err, SF_ERR_INPUT, "table cache: key '%s' is not 16 lowercase hex digits", key ? key : "");
  int len = snprintf(out, n, "%s/%s-%s.exr", dir, quantity, key);
  if (len < 0 || (size_t)len >= n)
    return sf_fail(err, SF_ERR_INPUT, "table cache: path in '%s' is too long", dir);
  return SF_OK;
}

/* Skips the "PATH: " that sf_table_read_exr puts before its reasons. */
static const char *reason_after_path(const char *message, const char *path) {
  size_t n = strlen(path);
  if (strncmp(message, path, n) == 0 && message[n] == ':' && message[n + 1] == ' ') return message + n + 2;
  return message;
}

int sf_table_cache_load(const char *dir, const sf_table_desc *desc, size_t max_bytes, sf_table *out,
                        sf_error *problem) {
  memset(out, 0, sizeof *out);
  char path[4096];
  sf_error inner = {0};
  if (sf_table_cache_path(dir, desc->quantity, desc->content_hash, path, sizeof path, &inner) != SF_OK) {
    sf_fail(problem, SF_ERR_INPUT, "%s", inner.message);
    return 0;
  }
  struct stat st;
  if (stat(path, &st) != 0) {
    if (errno == ENOENT || errno == ENOTDIR) return 0;   /* not cached yet */
    sf_fail(problem, SF_ERR_INPUT, "cache file %s is corrupt: cannot inspect it: %s", path, strerror(errno));
    return 0;
  }
  if (sf_table_read_exr(path, max_bytes, out, &inner) != SF_OK) {
    sf_fail(problem, SF_ERR_INPUT, "cache file %s is corrupt: %s", path, reason_after_path(inner.message, path));
    return 0;
  }
  if (!sf_table_desc_equal(&out->desc, desc)) {
    sf_fail(problem, SF_ERR_INPUT,
            "cache file %s is corrupt: it holds a different table (%s, %s, hash '%s') than its name says",
            path, out->desc.quantity, out->desc.parameterization, out->desc.content_hash);
    sf_table_free(out);
    return 0;
  }
  sf_cache_entry_used(path);
  return 1;
}

int sf_table_cache_store(const char *dir, const sf_table *t, sf_error *err) {
  char path[4096];
  if (sf_table_cache_path(dir, t->desc.quantity, t->desc.content_hash, path, sizeof path, err) != SF_OK)
    return SF_ERR_INPUT;
  if (sf_make_folders(dir, "table cache", err) != SF_OK) return SF_ERR_INPUT;
  return sf_table_write_exr(t, path, err);
}
