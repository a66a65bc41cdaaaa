#include "util/read_file.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

int sf_read_file(const char *path, const sf_file_rules *rules, char **text_out, size_t *len_out, sf_error *err) {
  FILE *f = fopen(path, "rb");
  if (!f)
    return sf_fail(err, SF_ERR_INPUT, "%s: %scannot open %s: %s", path, rules->where, rules->kind,
                   strerror(errno));
  /* A regular file within the limit: one piece a byte longer than it, so
   * that the first read ends short and the next finds the end. */
  struct stat st;
  size_t first = (size_t)1 << 16;
  if (fstat(fileno(f), &st) == 0 && S_ISREG(st.st_mode) && st.st_size >= 0 &&
      (unsigned long long)st.st_size < rules->max_bytes)
    first = (size_t)st.st_size + 1;
  size_t cap = 0, len = 0; /* cap bytes of text, plus one for the NUL */
  char *text = NULL;
  int rc = 0;
  for (;;) {
    if (len == cap) {
      if (cap > rules->max_bytes) {
        rc = sf_fail(err, SF_ERR_INPUT, "%s: %s%s too large (over %zu bytes)", path, rules->where, rules->kind,
                     rules->max_bytes);
        break;
      }
      size_t new_cap = cap ? 2 * cap : first;
      if (new_cap > rules->max_bytes + 1) new_cap = rules->max_bytes + 1;
      char *grown = realloc(text, new_cap + 1);
      if (!grown) {
        rc = sf_fail(err, SF_ERR_INTERNAL, "%s: out of memory reading the file", path);
        break;
      }
      text = grown;
      cap = new_cap;
    }
    size_t got = fread(text + len, 1, cap - len, f);
    len += got;
    if (got == 0) {
      if (ferror(f))
        rc = sf_fail(err, SF_ERR_INPUT, "%s: %scannot read %s: %s", path, rules->where, rules->kind,
                     strerror(errno));
      break;
    }
  }
  fclose(f);
  if (rc) {
    free(text);
    return rc;
  }
  text[len] = '\0';
  *text_out = text;
  *len_out = len;
  return 0;
}
