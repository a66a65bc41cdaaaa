#include "fit/candidate_cache.h"

#include <errno.h>
#include <fcntl.h>
#include <pthread.h>
#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "models/atmosphere_file.h"
#include "models/weights_file.h"
#include "util/atomic_file.h"
#include "util/hash64.h"
#include "util/make_folders.h"

static void append(sf_cache_key *k, const char *name, const char *value) {
  size_t len = strlen(k->text);
  snprintf(k->text + len, sizeof k->text - len, "%s=%s;", name, value);
}

void sf_cache_key_add_text(sf_cache_key *k, const char *name, const char *v) { append(k, name, v); }

void sf_cache_key_add_number(sf_cache_key *k, const char *name, double v) {
  char text[40];
  snprintf(text, sizeof text, "%.17g", v);
  append(k, name, text);
}

/* The running executable's bytes, hashed once per process (about 5 ms for
 * 5 MB): a constant of the process, not state. Where they cannot be read
 * (an execute-only binary of another user), its file's identity (device,
 * inode, size, modification time), and where not even that, this process
 * alone: a cache that cannot tell executables apart is not reused. */
static char exe_identity[128];
static pthread_once_t exe_identity_once = PTHREAD_ONCE_INIT;

static int hash_exe_bytes(void) {
  int fd = open("/proc/self/exe", O_RDONLY);
  if (fd < 0) return 0;
  uint64_t h = SF_FNV1A64_OFFSET;
  long long size = 0;
  unsigned char buf[1 << 16];
  ssize_t got;
  while ((got = read(fd, buf, sizeof buf)) != 0) {
    if (got < 0 && errno == EINTR) continue;
    if (got < 0) break;
    h = sf_fnv1a64(h, buf, (size_t)got);
    size += got;
  }
  close(fd);
  if (got != 0) return 0;
  char hex[17];
  sf_hash64_hex(h, hex);
  snprintf(exe_identity, sizeof exe_identity, "%lld bytes, fnv1a64 %s", size, hex);
  return 1;
}

static void identify_exe(void) {
  if (hash_exe_bytes()) return;
  struct stat st;
  struct timespec now;
  if (stat("/proc/self/exe", &st) == 0)
    snprintf(exe_identity, sizeof exe_identity, "file %llu:%llu, %lld bytes, modified %lld.%09ld",
             (unsigned long long)st.st_dev, (unsigned long long)st.st_ino, (long long)st.st_size,
             (long long)st.st_mtim.tv_sec, (long)st.st_mtim.tv_nsec);
  else if (clock_gettime(CLOCK_REALTIME, &now) == 0)
    snprintf(exe_identity, sizeof exe_identity, "unknown, process %ld at %lld.%09ld", (long)getpid(),
             (long long)now.tv_sec, now.tv_nsec);
  else
    snprintf(exe_identity, sizeof exe_identity, "unknown, process %ld", (long)getpid());
}

/* The machine's, read once per process as the executable's is. */
static char machine_identity[256];
static pthread_once_t machine_identity_once = PTHREAD_ONCE_INIT;

static void identify_machine(void) {
  char model[200] = "";
  FILE *f = fopen("/proc/cpuinfo", "r");
  char line[512];
  while (f && fgets(line, sizeof line, f)) {
    const char *colon = strchr(line, ':');
    if (strncmp(line, "model name", 10) != 0 || !colon) continue;
    snprintf(model, sizeof model, "%s", colon + (colon[1] == ' ' ? 2 : 1));
    model[strcspn(model, "\n")] = '\0';
    break;
  }
  if (f) fclose(f);
  snprintf(machine_identity, sizeof machine_identity, "%s; %ld processors", model, sysconf(_SC_NPROCESSORS_ONLN));
}

void sf_cache_machine_identity(char *out, size_t n) {
  pthread_once(&machine_identity_once, identify_machine);
  snprintf(out, n, "%s", machine_identity);
}

void sf_cache_code_identity(char *out, size_t n) {
  pthread_once(&exe_identity_once, identify_exe);
  snprintf(out, n, "%s; exe %s", SF_CANDIDATE_CODE_VERSION, exe_identity);
}

void sf_cache_key_begin(sf_cache_key *k, const char *model, const sf_candidate_inputs *in) {
  k->text[0] = '\0';
  char hash[17];
  sf_atmosphere_hash_hex(in->atm, hash);
  append(k, "model", model);
  char code[256];
  sf_cache_code_identity(code, sizeof code);
  append(k, "code", code);
  append(k, "atmosphere", hash);
  const sf_scene_domain *d = &in->domain;
  sf_cache_key_add_number(k, "h_min", d->h_min_km);
  sf_cache_key_add_number(k, "h_max", d->h_max_km);
  sf_cache_key_add_number(k, "mu_min", d->mu_min);
  sf_cache_key_add_number(k, "mu_max", d->mu_max);
  sf_cache_key_add_number(k, "mu_s_min", d->mu_s_min);
  sf_cache_key_add_number(k, "mu_s_max", d->mu_s_max);
  sf_cache_key_add_number(k, "seed", (double)in->seed);
  sf_cache_key_add_number(k, "quick", in->quick);
}

void sf_cache_key_add_tables(sf_cache_key *k, const sf_candidate_inputs *in) {
  const sf_table_params *p = &in->tables->params;
  sf_cache_key_add_number(k, "param_kind", p->kind);
  const sf_table_resolution *r = &p->res;
  sf_cache_key_add_number(k, "t_mu", r->transmittance_mu);
  sf_cache_key_add_number(k, "t_h", r->transmittance_h);
  sf_cache_key_add_number(k, "s_h", r->scattering_h);
  sf_cache_key_add_number(k, "s_mu", r->scattering_mu);
  sf_cache_key_add_number(k, "s_mu_s", r->scattering_mu_s);
  sf_cache_key_add_number(k, "s_nu", r->scattering_nu);
  sf_cache_key_add_number(k, "i_mu_s", r->irradiance_mu_s);
  sf_cache_key_add_number(k, "i_h", r->irradiance_h);
  sf_cache_key_add_number(k, "restricted", p->restricted);
  sf_cache_key_add_number(k, "tables_h_min", p->h_min_km);
  sf_cache_key_add_number(k, "tables_h_max", p->h_max_km);
  sf_cache_key_add_number(k, "tables_mu_s_max", p->mu_s_max);
  sf_cache_key_add_number(k, "orders", in->orders);
}

int sf_cache_path(const char *cache_dir, const char *sub, const char *model, const sf_cache_key *k,
                  char *path, size_t n, sf_error *err) {
  path[0] = '\0';
  if (!cache_dir) return SF_OK;
  char dir[4200];
  snprintf(dir, sizeof dir, "%s/%s", cache_dir, sub);
  if (sf_make_folders(dir, "cache", err) != SF_OK) return err->status;
  uint64_t h = sf_fnv1a64(SF_FNV1A64_OFFSET, k->text, strlen(k->text));
  int w = snprintf(path, n, "%s/%s-%016" PRIx64 ".json", dir, model, h);
  if (w < 0 || (size_t)w >= n) return sf_fail(err, SF_ERR_INPUT, "cache path too long: %s", dir);
  return SF_OK;
}

int sf_folder_writable(const char *dir, const char *role, sf_error *err) {
  /* asked of the file system, not by making a file: a probe file left by
   * a run killed between making and removing it was an unknown file in
   * the cache (tests/cli_build_atomic.sh) */
  if (faccessat(AT_FDCWD, dir, W_OK | X_OK, AT_EACCESS) != 0) {
    int e = errno;
    return sf_fail(err, sf_write_error_status(e), "%s folder %s cannot be written: %s", role, dir, strerror(e));
  }
  return SF_OK;
}

int sf_cache_weights_belong(const sf_weights *w, const sf_atmosphere *atm, const sf_scene_domain *domain,
                            sf_error *err) {
  char hash[17];
  sf_atmosphere_hash_hex(atm, hash);
  if (strcmp(w->atmosphere_hash, hash) != 0)
    return sf_fail(err, SF_ERR_INPUT, "%s: the fit of atmosphere %s (hash %s), not of %s (hash %s)", w->source,
                   w->atmosphere.name, w->atmosphere_hash, atm->name, hash);
  if (!sf_scene_domain_same(&w->domain, domain))
    return sf_fail(err, SF_ERR_INPUT, "%s: a fit over another domain (h %.17g..%.17g km, mu %.17g..%.17g, mu_s "
                   "%.17g..%.17g)", w->source, w->domain.h_min_km, w->domain.h_max_km, w->domain.mu_min,
                   w->domain.mu_max, w->domain.mu_s_min, w->domain.mu_s_max);
  return SF_OK;
}

int sf_cache_fit_belongs(const char *path, const char *model, const sf_atmosphere *atm,
                         const sf_scene_domain *domain, sf_error *err) {
  sf_weights w;
  if (sf_weights_load_file(path, model, &w, err) != SF_OK) return err->status;
  int status = sf_cache_weights_belong(&w, atm, domain, err);
  sf_weights_free(&w);
  return status;
}

int sf_cache_exists(const char *path) {
  struct stat st;
  return path[0] && stat(path, &st) == 0 && S_ISREG(st.st_mode);
}

int sf_copy_file(const char *src, const char *dst, sf_error *err) {
  FILE *in = fopen(src, "rb");
  if (!in) return sf_fail(err, SF_ERR_INPUT, "%s: cannot open", src);
  sf_atomic_file out;
  if (sf_atomic_open(&out, dst, err) != SF_OK) {
    fclose(in);
    return err->status;
  }
  char buf[65536];
  size_t got;
  int ok = 1;
  while ((got = fread(buf, 1, sizeof buf, in)) > 0)
    if (fwrite(buf, 1, got, out.stream) != got) ok = 0;
  if (ferror(in)) ok = 0;
  fclose(in);
  if (!ok) {
    sf_atomic_abort(&out);
    return sf_fail(err, SF_ERR_INPUT, "cannot copy %s to %s", src, dst);
  }
  return sf_atomic_commit(&out, err);
}

int sf_copy_weights_to_work_dir(const char *src, const char *work_dir, const char *name, char *dst, size_t n,
                                sf_error *err) {
  int w = snprintf(dst, n, "%s/%s.json", work_dir, name);
  if (w < 0 || (size_t)w >= n) {
    if (n > 0) dst[0] = '\0';
    return sf_fail(err, SF_ERR_INPUT, "%s: weights path too long (%zu bytes at most)", work_dir, n - 1);
  }
  return sf_copy_file(src, dst, err);
}
