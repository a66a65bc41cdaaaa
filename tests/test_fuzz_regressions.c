/* Inputs that once broke a loader of user input (found by the libFuzzer
 * targets of tests/fuzz/, or by the sanitized suite) stay fixed: every file
 * under tests/fuzz/regressions/LOADER/ is fed to its loader, which must
 * reject it cleanly — SF_ERR_INPUT, a one-line message naming the source, an
 * empty result — and not crash (the sanitized suite, scripts/
 * test_sanitized.sh, also catches a leak or a read out of bounds there).
 * The seed corpus tests/fuzz/corpus/LOADER/ must load without error, so the
 * fuzzers start from inputs that reach past the first validation.
 *
 * The eval CSV reader is part of the skyfit binary, not of skyfit_core, so
 * its inputs go through `skyfit eval` (SKYFIT_BIN): exit 2, stdout empty,
 * one line on stderr. */
#include <dirent.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "data/table_exr.h"
#include "models/atmosphere_file.h"
#include "models/scene_file.h"
#include "models/weights_file.h"
#include "tests/check.h"

#define MAX_FILES 256
#define MAX_INPUT_BYTES ((size_t)4 << 20)

typedef struct file_list {
  int n;
  char names[MAX_FILES][256];
} file_list;

static int compare_names(const void *a, const void *b) { return strcmp(a, b); }

/* Plain files of dir, sorted (the test's output is the same every run). */
static void list_files(const char *dir, file_list *out) {
  out->n = 0;
  DIR *d = opendir(dir);
  if (!d) return;
  for (struct dirent *e; (e = readdir(d)) != NULL;) {
    if (e->d_name[0] == '.' || out->n == MAX_FILES) continue;
    snprintf(out->names[out->n++], sizeof out->names[0], "%s", e->d_name);
  }
  closedir(d);
  qsort(out->names, (size_t)out->n, sizeof out->names[0], compare_names);
}

/* The whole file, NUL-terminated (a NUL inside ends the text, as it does
 * for the fuzz targets' fuzz_text). */
static char *read_whole(const char *path) {
  FILE *f = fopen(path, "rb");
  if (!f) return NULL;
  char *text = malloc(MAX_INPUT_BYTES + 1);
  size_t n = text ? fread(text, 1, MAX_INPUT_BYTES, f) : 0;
  fclose(f);
  if (text) text[n] = '\0';
  return text;
}

/* A clean rejection: SF_ERR_INPUT with one line naming the source. */
static int clean_rejection(int status, const sf_error *err, const char *source) {
  return status == SF_ERR_INPUT && err->status == SF_ERR_INPUT && err->message[0] &&
         strchr(err->message, '\n') == NULL && strncmp(err->message, source, strlen(source)) == 0;
}

typedef enum { EXPECT_ACCEPT, EXPECT_REJECT } expectation;

static void report(const char *loader, const char *file, expectation want, int status,
                   const sf_error *err, int ok) {
  printf("%s %-10s %-44s %s: status %d%s%s\n", ok ? "ok  " : "FAIL", loader, file,
         want == EXPECT_ACCEPT ? "accept" : "reject", status, err->message[0] ? ": " : "",
         err->message);
  check_report(ok, file, __FILE__, __LINE__);
}

static void check_json_loader(const char *src_dir, const char *loader, const char *sub, expectation want) {
  char dir[4096];
  snprintf(dir, sizeof dir, "%s/tests/fuzz/%s/%s", src_dir, sub, loader);
  file_list *files = malloc(sizeof *files);
  list_files(dir, files);
  CHECK(files->n > 0);
  for (int i = 0; i < files->n; ++i) {
    char path[4400];
    snprintf(path, sizeof path, "%s/%s", dir, files->names[i]);
    char *text = read_whole(path);
    if (!text) {
      CHECK(text != NULL);
      continue;
    }
    const char *source = files->names[i];
    sf_error err = {0};
    int status, empty = 1;
    if (strcmp(loader, "atmosphere") == 0) {
      sf_atmosphere *atm = calloc(1, sizeof *atm);
      status = sf_atmosphere_load_string(text, source, atm, &err);
      free(atm);
    } else if (strcmp(loader, "scene") == 0) {
      char base[4200];
      snprintf(base, sizeof base, "%s/tests/fuzz/scene_files", src_dir);
      sf_scene *scene = calloc(1, sizeof *scene);
      status = sf_scene_load_string(text, source, base, scene, &err);
      free(scene);
    } else {
      sf_weights *w = calloc(1, sizeof *w);
      status = sf_weights_load_string(text, source, NULL, w, &err);
      empty = status == SF_OK || w->root == NULL;
      sf_weights_free(w);
      free(w);
    }
    int ok = want == EXPECT_ACCEPT ? status == SF_OK && err.status == SF_OK
                                   : clean_rejection(status, &err, source) && empty;
    report(loader, files->names[i], want, status, &err, ok);
    free(text);
  }
  free(files);
}

static void check_table_loader(const char *src_dir, const char *sub, expectation want) {
  char dir[4096];
  snprintf(dir, sizeof dir, "%s/tests/fuzz/%s/table_exr", src_dir, sub);
  file_list *files = malloc(sizeof *files);
  list_files(dir, files);
  if (want == EXPECT_ACCEPT) CHECK(files->n > 0);
  for (int i = 0; i < files->n; ++i) {
    char path[4400];
    snprintf(path, sizeof path, "%s/%s", dir, files->names[i]);
    sf_table t;
    sf_error err = {0};
    /* The bound the table fuzzer reads with (tests/fuzz/fuzz_table_exr.c). */
    int status = sf_table_read_exr(path, (size_t)64 << 20, &t, &err);
    int ok = want == EXPECT_ACCEPT ? status == SF_OK
                                   : clean_rejection(status, &err, path) && t.data == NULL;
    report("table_exr", files->names[i], want, status, &err, ok);
    if (status == SF_OK) sf_table_free(&t);
  }
  free(files);
}

/* `skyfit eval QUANTITY < path`: exit status, stdout bytes, stderr lines. */
static int run_eval(const char *bin, const char *quantity, const char *path, const char *tmp_dir,
                    long *stdout_bytes, int *stderr_lines) {
  char out_path[4200], err_path[4200];
  snprintf(out_path, sizeof out_path, "%s/stdout", tmp_dir);
  snprintf(err_path, sizeof err_path, "%s/stderr", tmp_dir);
  pid_t pid = fork();
  if (pid == 0) {
    int in = open(path, O_RDONLY);
    int out = open(out_path, O_WRONLY | O_CREAT | O_TRUNC, 0600);
    int err = open(err_path, O_WRONLY | O_CREAT | O_TRUNC, 0600);
    if (in < 0 || out < 0 || err < 0) _exit(127);
    dup2(in, 0);
    dup2(out, 1);
    dup2(err, 2);
    execl(bin, bin, "eval", quantity, (char *)NULL);
    _exit(127);
  }
  int wstatus = 0;
  if (pid < 0 || waitpid(pid, &wstatus, 0) != pid) return -1;
  struct stat st;
  *stdout_bytes = stat(out_path, &st) == 0 ? (long)st.st_size : -1;
  *stderr_lines = 0;
  FILE *f = fopen(err_path, "r");
  if (f) {
    int c, last = '\n';
    while ((c = fgetc(f)) != EOF) {
      if (c == '\n') ++*stderr_lines;
      last = c;
    }
    if (last != '\n') ++*stderr_lines;
    fclose(f);
  }
  return WIFEXITED(wstatus) ? WEXITSTATUS(wstatus) : 128 + WTERMSIG(wstatus);
}

static void check_csv_regressions(const char *src_dir, const char *bin) {
  char dir[4096], tmp_dir[] = "/tmp/skyfit-fuzz-regressions-XXXXXX";
  snprintf(dir, sizeof dir, "%s/tests/fuzz/regressions/csv_points", src_dir);
  if (!mkdtemp(tmp_dir)) {
    CHECK(!"mkdtemp");
    return;
  }
  file_list *files = malloc(sizeof *files);
  list_files(dir, files);
  for (int i = 0; i < files->n; ++i) {
    char path[4400];
    snprintf(path, sizeof path, "%s/%s", dir, files->names[i]);
    /* The quantity whose columns the file's header names, so that the
     * reader gets past the header to the rows. */
    char *text = read_whole(path);
    const char *quantity = text && strncmp(text, "h_km,mu,mu_s,nu", 15) == 0 ? "single_scattering" : "optical_depth";
    free(text);
    long out_bytes = -1;
    int err_lines = -1;
    int rc = run_eval(bin, quantity, path, tmp_dir, &out_bytes, &err_lines);
    int ok = rc == 2 && out_bytes == 0 && err_lines == 1;
    printf("%s %-10s %-44s reject: skyfit eval %s exit %d (want 2), stdout %ld bytes (want 0), "
           "stderr %d lines (want 1)\n",
           ok ? "ok  " : "FAIL", "csv_points", files->names[i], quantity, rc, out_bytes, err_lines);
    check_report(ok, files->names[i], __FILE__, __LINE__);
  }
  CHECK(files->n > 0);
  free(files);
  char p[4300];
  snprintf(p, sizeof p, "%s/stdout", tmp_dir);
  unlink(p);
  snprintf(p, sizeof p, "%s/stderr", tmp_dir);
  unlink(p);
  rmdir(tmp_dir);
}

int main(void) {
  const char *src_dir = getenv("SKYFIT_SOURCE_DIR");
  const char *bin = getenv("SKYFIT_BIN");
  if (!src_dir || !bin) {
    printf("SKYFIT_SOURCE_DIR and SKYFIT_BIN must be set (ctest sets them)\n");
    return 1;
  }
  static const char *const json_loaders[] = {"atmosphere", "scene", "weights"};
  for (int i = 0; i < 3; ++i) {
    check_json_loader(src_dir, json_loaders[i], "corpus", EXPECT_ACCEPT);
    check_json_loader(src_dir, json_loaders[i], "regressions", EXPECT_REJECT);
  }
  check_table_loader(src_dir, "corpus", EXPECT_ACCEPT);
  check_table_loader(src_dir, "regressions", EXPECT_REJECT);
  check_csv_regressions(src_dir, bin);
  return check_summary();
}
