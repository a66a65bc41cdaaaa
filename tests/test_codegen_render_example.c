/* The example renderer (examples/render_sky/render_sky.c) against skyfit's
 * own views code (issue 7):
 *  - a Hosek weights file (SPEC §8) holding the published Hosek-Wilkie 2012
 *    RGB dataset's control points at turbidity 2, albedo 0 (paper order
 *    A..I; radiance scaled by 1/50 to the reference's units, sun irradiance
 *    1, so that exposure 1 x irradiance 6 gives a daylight picture);
 *  - `skyfit codegen --lang c` emits the header; the example is compiled
 *    against it alone (C99, -Wall -Wextra -Werror -pedantic, libpng) and
 *    renders the ground-noon view to PNG;
 *  - the reference: the same view through models/views_standard.h (camera,
 *    pixel inputs, tone map) with the double model (sf_sky_radiance_clamped),
 *    pixels below the horizon black as in the example.
 * Checked: the PNG decodes at the view's size, is not blank (channel spread
 * > 20 levels), its mean colour is within 0.25 of 255 levels of the
 * reference per channel, and no pixel differs by more than 1 level (float32
 * vs double can only move an 8-bit rounding). */
#include <math.h>
#include <png.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "check.h"
#include "codegen/emit_sky.h"
#include "models/atmosphere_file.h"
#include "models/hosek_dataset.h"
#include "models/hosek_sky_model.h"
#include "models/views_standard.h"
#include "models/weights_file.h"
#include "util/constants.h"

#define WIDTH 192
#define HEIGHT 108
#define TURBIDITY_INDEX 1    /* turbidity 2 */
#define RADIANCE_SCALE 0.02

static int run(const char *command) {
  fflush(stdout);
  int status = system(command);
  if (status != 0) printf("command failed (%d): %s\n", status, command);
  return status;
}

/* The dataset's control points in our model's layout (models/hosek_sky_model.h). */
static void model_from_dataset(const sf_hosek_dataset *d, sf_elevation_sky_model *m) {
  memset(m, 0, sizeof *m);
  m->form = SF_SKY_FORM_HOSEK;
  m->n_coeffs = sf_sky_form_n_coeffs(SF_SKY_FORM_HOSEK);
  m->n_channels = 3;
  m->elevation_min_rad = 0.0;
  m->elevation_max_rad = 0.5 * SF_PI;
  for (int k = 0; k < 3; ++k)
    for (int j = 0; j < SF_BEZIER_POINTS; ++j) {
      for (int i = 0; i < 9; ++i) {
        int stored = i == 7 ? 8 : i == 8 ? 7 : i;   /* the file stores H and I swapped */
        m->coefficients[k][j][i] = d->coefficients[k][0][TURBIDITY_INDEX][j][stored];
      }
      m->scale[k][j] = RADIANCE_SCALE * d->radiances[k][0][TURBIDITY_INDEX][j];
    }
}

static int write_weights(const char *path, const sf_elevation_sky_model *m) {
  sf_atmosphere atm;
  sf_atmosphere_default(&atm);
  sf_scene_domain domain = {0.0, 0.0, 0.0, 1.0, 0.0, 1.0};
  cJSON *doc = sf_weights_new("hosek", "sky_radiance", &atm, &domain);
  sf_elevation_sky_add_params(doc, m);
  cJSON_AddNumberToObject(sf_weights_metrics(doc), "rel_rmse", 0.0);
  sf_error err;
  sf_error_clear(&err);
  int status = sf_weights_write(doc, path, &err);
  if (status) printf("%s\n", err.message);
  cJSON_Delete(doc);
  return status;
}

static void reference_render(const sf_elevation_sky_model *m, unsigned char *rgb) {
  sf_atmosphere atm;
  sf_atmosphere_default(&atm);
  const sf_view_def *views = NULL, *noon = NULL;
  int n = sf_standard_radiance_views(&views);
  for (int v = 0; v < n; ++v)
    if (strcmp(views[v].name, "ground-noon") == 0) noon = &views[v];
  if (!CHECK(noon != NULL)) return;
  sf_view_camera cam;
  sf_view_camera_make(noon, &atm, WIDTH, HEIGHT, &cam);
  float *linear = malloc(sizeof(float) * 3 * WIDTH * HEIGHT);
  for (int j = 0; j < HEIGHT; ++j)
    for (int i = 0; i < WIDTH; ++i) {
      double in[4], L[SF_MAX_CHANNELS] = {0.0, 0.0, 0.0};
      sf_view_pixel_inputs(&cam, &atm, i, j, in);
      if (in[1] >= 0.0) sf_sky_radiance_clamped(m, in[1], in[2], in[3], L);
      for (int k = 0; k < 3; ++k)
        linear[3 * (j * WIDTH + i) + k] = (float)(noon->exposure * SF_VIEW_SUN_IRRADIANCE * L[k]);
    }
  sf_view_to_srgb8(linear, (size_t)WIDTH * HEIGHT, 1, rgb);
  free(linear);
}

int main(void) {
  const char *bin = getenv("SKYFIT_BIN"), *src = getenv("SKYFIT_SOURCE_DIR");
  if (!CHECK(bin && src)) return check_summary();
  char dir[] = "/tmp/skyfit_render_XXXXXX";
  if (!mkdtemp(dir)) return 1;
  printf("working in %s\n", dir);
  sf_hosek_dataset *data = malloc(sizeof *data);
  sf_error err;
  sf_error_clear(&err);
  if (!CHECK(sf_hosek_dataset_load_default(data, &err) == SF_OK)) {
    printf("%s\n", err.message);
    return check_summary();
  }
  sf_elevation_sky_model m;
  model_from_dataset(data, &m);
  free(data);

  char path[512], cmd[4096];
  snprintf(path, sizeof path, "%s/hosek.json", dir);
  CHECK(write_weights(path, &m) == SF_OK);
  snprintf(cmd, sizeof cmd, "%s codegen --weights %s --lang c --out %s --name sky --quiet", bin, path, dir);
  CHECK(run(cmd) == 0);
  snprintf(cmd, sizeof cmd,
           "cc -std=c99 -O2 -Wall -Wextra -Werror -pedantic -I%s -DSKYFIT_SKY_HEADER='\"sky.h\"' "
           "%s/examples/render_sky/render_sky.c -o %s/render_sky -lpng -lm && %s/render_sky %s/sky.png %d %d",
           dir, src, dir, dir, dir, WIDTH, HEIGHT);
  CHECK(run(cmd) == 0);

  png_image image;
  memset(&image, 0, sizeof image);
  image.version = PNG_IMAGE_VERSION;
  snprintf(path, sizeof path, "%s/sky.png", dir);
  unsigned char *got = NULL;
  if (CHECK(png_image_begin_read_from_file(&image, path) != 0)) {
    image.format = PNG_FORMAT_RGB;
    got = malloc(PNG_IMAGE_SIZE(image));
    CHECK(png_image_finish_read(&image, NULL, got, 0, NULL) != 0);
  }
  CHECK(image.width == WIDTH && image.height == HEIGHT);
  unsigned char *want = calloc(3 * WIDTH * HEIGHT, 1);
  reference_render(&m, want);
  if (got && image.width == WIDTH && image.height == HEIGHT) {
    double mean_got[3] = {0}, mean_want[3] = {0};
    int lo = 255, hi = 0, worst = 0, differing = 0;
    for (int p = 0; p < WIDTH * HEIGHT; ++p)
      for (int k = 0; k < 3; ++k) {
        int g = got[3 * p + k], w = want[3 * p + k];
        mean_got[k] += g;
        mean_want[k] += w;
        lo = g < lo ? g : lo;
        hi = g > hi ? g : hi;
        worst = abs(g - w) > worst ? abs(g - w) : worst;
        differing += g != w;
      }
    for (int k = 0; k < 3; ++k) {
      mean_got[k] /= WIDTH * HEIGHT;
      mean_want[k] /= WIDTH * HEIGHT;
    }
    printf("example mean colour (%.3f, %.3f, %.3f), reference (%.3f, %.3f, %.3f); range %d..%d; "
           "%d of %d channel values differ, by at most %d\n",
           mean_got[0], mean_got[1], mean_got[2], mean_want[0], mean_want[1], mean_want[2], lo, hi, differing,
           3 * WIDTH * HEIGHT, worst);
    CHECK(hi - lo > 20);   /* not blank */
    for (int k = 0; k < 3; ++k) CHECK_ABS(mean_got[k], mean_want[k], 0.25);
    CHECK(worst <= 1);
  }
  free(got);
  free(want);
  if (check_failed_count == 0 && !getenv("SKYFIT_RENDER_KEEP")) {   /* keep: to look at the picture */
    snprintf(cmd, sizeof cmd, "rm -rf %s", dir);
    run(cmd);
  }
  return check_summary();
}
