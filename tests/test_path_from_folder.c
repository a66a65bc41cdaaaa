/* util/path_from_folder.h: the report names the emitted headers from its
 * own folder, as it names its views: inside it relative, outside it
 * absolute, links and "." / ".." resolved in the folders. */
#define _XOPEN_SOURCE 700 /* realpath, mkdtemp, symlink */
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "tests/check.h"
#include "util/path_from_folder.h"

static int gives(const char *folder, const char *path, const char *want) {
  char out[4096];
  int rc = sf_path_from_folder(folder, path, out, sizeof out);
  int ok = rc == 0 && strcmp(out, want) == 0;
  printf("%s %s from %s: %s (want %s)\n", ok ? "ok  " : "FAIL", path, folder, out, want);
  return ok;
}

int main(void) {
  char root[] = "/tmp/skyfit-path-from-folder-XXXXXX";
  CHECK(mkdtemp(root) != NULL);
  char real_root[PATH_MAX];
  CHECK(realpath(root, real_root) != NULL);
  char out_dir[600], sub[600], other[600], link[600], want[PATH_MAX + 64], path[1400];
  snprintf(out_dir, sizeof out_dir, "%s/out", root);
  snprintf(sub, sizeof sub, "%s/out/include", root);
  snprintf(other, sizeof other, "%s/elsewhere", root);
  snprintf(link, sizeof link, "%s/out-link", root);
  CHECK(mkdir(out_dir, 0777) == 0 && mkdir(sub, 0777) == 0 && mkdir(other, 0777) == 0);
  CHECK(symlink(out_dir, link) == 0);

  /* the default build: OUT/sky.h, named from OUT */
  snprintf(path, sizeof path, "%s/sky.h", out_dir);
  CHECK(gives(out_dir, path, "sky.h"));
  snprintf(path, sizeof path, "%s/include/sky.glsl", out_dir);
  CHECK(gives(out_dir, path, "include/sky.glsl"));
  /* through a link and through ".." */
  snprintf(path, sizeof path, "%s/sky.h", link);
  CHECK(gives(out_dir, path, "sky.h"));
  snprintf(path, sizeof path, "%s/include/../sky.h", out_dir);
  CHECK(gives(link, path, "sky.h"));
  /* outside OUT: absolute, even where a prefix of the name matches
   * ("out-link" is not inside "out") */
  snprintf(path, sizeof path, "%s/sky.h", other);
  snprintf(want, sizeof want, "%s/elsewhere/sky.h", real_root);
  CHECK(gives(out_dir, path, want));
  char outer[600];
  snprintf(outer, sizeof outer, "%s/out2", root);
  CHECK(mkdir(outer, 0777) == 0);
  snprintf(path, sizeof path, "%s/sky.h", outer);
  snprintf(want, sizeof want, "%s/out2/sky.h", real_root);
  CHECK(gives(out_dir, path, want));
  /* a relative path, from the working folder */
  CHECK(chdir(root) == 0);
  CHECK(gives("out", "out/sky.h", "sky.h"));
  snprintf(want, sizeof want, "%s/elsewhere/sky.h", real_root);
  CHECK(gives("out", "elsewhere/sky.h", want));
  snprintf(want, sizeof want, "%s/out/sky.h", real_root);   /* above the folder: absolute too */
  CHECK(gives("out/include", "out/sky.h", want));
  /* spelled below the folder: the rest, whether or not its folders exist
   * yet (a build's report names weights files still in its staging
   * folder); "x/../" is not taken as below */
  CHECK(gives("staged", "staged/weights/sigmoid.json", "weights/sigmoid.json"));
  CHECK(gives("out/", "out/weights/sigmoid.json", "weights/sigmoid.json"));
  /* --out with a trailing slash: the build spells its files OUT + "/sky.h",
   * "out//sky.h" (relative, not "/sky.h"), "."'s ".//sky.h" */
  CHECK(gives("out/", "out//sky.h", "sky.h"));
  CHECK(gives("./", ".//out/sky.h", "out/sky.h"));
  CHECK(gives("out", "out//.staging.1/weights/x.json", ".staging.1/weights/x.json"));
  snprintf(want, sizeof want, "%s/sky.h", real_root);
  CHECK(gives("out", "out/../sky.h", want));
  /* a folder that does not exist: the path as given, -1 */
  char out[64];
  CHECK(sf_path_from_folder("out", "missing/sky.h", out, sizeof out) == -1 && strcmp(out, "missing/sky.h") == 0);
  /* too long for out: -1, nothing cut into another path */
  CHECK(sf_path_from_folder("out", "elsewhere/sky.h", out, 8) == -1);

  snprintf(path, sizeof path, "rm -rf '%s'", root);
  CHECK(system(path) == 0);
  return check_summary();
}
