/* A small renderer that uses only an emitted C header (skyfit codegen
 * --lang c) and libpng: the standard ground-noon view of seed 000 §11.4
 * (models/views_standard.h) with the Hosek sky radiance the header holds,
 * tone mapped as seed 000 §11.5, written as an 8-bit sRGB PNG.
 *
 * Build (the header is named by SKYFIT_SKY_HEADER, default "sky.h";
 * codegen's --name sets the file's name, --out an existing folder):
 *   mkdir -p gen
 *   skyfit codegen --weights hosek.json --lang c --name sky --out gen
 *   cc -std=c99 -O2 -Igen -DSKYFIT_SKY_HEADER='"sky.h"' render_sky.c -o render_sky -lpng -lm
 *   ./render_sky sky.png [WIDTH HEIGHT]
 *
 * The camera is written out here (the example depends on nothing of
 * skyfit's but the header): a viewer on the ground, pinhole camera pitched
 * up 3° (the ground-noon view of models/views_standard.h), 60° vertical
 * field of view, the horizontal one following the aspect ratio; the sun
 * overhead; exposure 1 and sun irradiance 6. World frame: planet centre at
 * the origin, viewer at (0, 0, R); forward is +x tilted up by the pitch,
 * right is -y. Pixel (i, j), j = 0 the top row:
 * direction ∝ forward + x right + y up, x = (2 (i + 1/2) / W - 1) tan(hfov/2),
 * y = (1 - 2 (j + 1/2) / H) tan(vfov/2). Model inputs: mu = d.z (the zenith
 * is +z at the viewer), mu_s = s.z, nu = d.s. Hosek is a model of the sky
 * above the horizon: pixels looking below it are left black. */
#include <math.h>
#include <png.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifndef SKYFIT_SKY_HEADER
#define SKYFIT_SKY_HEADER "sky.h"
#endif
#include SKYFIT_SKY_HEADER

#define PI 3.14159265358979323846
#define PITCH_DEG 3.0
#define VFOV_DEG 60.0
#define SUN_ELEVATION_DEG 90.0
#define EXPOSURE 1.0
#define SUN_IRRADIANCE 6.0

static unsigned char to_srgb8(double exposed) {
  /* seed 000 §11.5: t(x) = 1 - exp(-x), then the sRGB transfer function */
  double x = exposed > 0.0 ? 1.0 - exp(-exposed) : 0.0;
  double s = x <= 0.0031308 ? 12.92 * x : 1.055 * pow(x, 1.0 / 2.4) - 0.055;
  long v = lround(255.0 * s);
  return (unsigned char)(v < 0 ? 0 : v > 255 ? 255 : v);
}

static double clamp1(double x) { return x < -1.0 ? -1.0 : x > 1.0 ? 1.0 : x; }

int main(int argc, char **argv) {
  int width = 192, height = 108;
  if (argc != 2 && argc != 4) {
    fprintf(stderr, "usage: %s OUT.png [WIDTH HEIGHT]\n", argv[0]);
    return 2;
  }
  if (argc == 4) {
    width = atoi(argv[2]);
    height = atoi(argv[3]);
    if (width < 1 || height < 1 || width > 16384 || height > 16384) {
      fprintf(stderr, "%s: WIDTH and HEIGHT must be 1..16384\n", argv[0]);
      return 2;
    }
  }
  double pitch = PITCH_DEG * PI / 180.0, tan_v = tan(0.5 * VFOV_DEG * PI / 180.0);
  double tan_h = tan_v * (double)width / (double)height;
  double forward[3] = {cos(pitch), 0.0, sin(pitch)}, right[3] = {0.0, -1.0, 0.0};
  double up[3] = {-sin(pitch), 0.0, cos(pitch)};
  double e = SUN_ELEVATION_DEG * PI / 180.0;
  double sun[3] = {cos(e), 0.0, sin(e)};
  unsigned char *rgb = malloc(3 * (size_t)width * (size_t)height);
  if (!rgb) {
    fprintf(stderr, "%s: out of memory\n", argv[0]);
    return 1;
  }
  for (int j = 0; j < height; ++j)
    for (int i = 0; i < width; ++i) {
      double x = (2.0 * (i + 0.5) / width - 1.0) * tan_h, y = (1.0 - 2.0 * (j + 0.5) / height) * tan_v;
      double d[3], n = 0.0;
      for (int k = 0; k < 3; ++k) {
        d[k] = forward[k] + x * right[k] + y * up[k];
        n += d[k] * d[k];
      }
      n = sqrt(n);
      for (int k = 0; k < 3; ++k) d[k] /= n;
      double mu = clamp1(d[2]), mu_s = clamp1(sun[2]);
      double nu = clamp1(d[0] * sun[0] + d[1] * sun[1] + d[2] * sun[2]);
      unsigned char *p = rgb + 3 * ((size_t)j * (size_t)width + (size_t)i);
      if (mu < 0.0) {
        p[0] = p[1] = p[2] = 0;
        continue;
      }
      skyfit_vec3 L = skyfit_hosek_sky_radiance((float)mu, (float)mu_s, (float)nu);
      double scale = EXPOSURE * SUN_IRRADIANCE;
      p[0] = to_srgb8(scale * L.x);
      p[1] = to_srgb8(scale * L.y);
      p[2] = to_srgb8(scale * L.z);
    }
  png_image image;
  memset(&image, 0, sizeof image);
  image.version = PNG_IMAGE_VERSION;
  image.width = (png_uint_32)width;
  image.height = (png_uint_32)height;
  image.format = PNG_FORMAT_RGB;
  int ok = png_image_write_to_file(&image, argv[1], 0, rgb, 0, NULL);
  free(rgb);
  if (!ok) {
    fprintf(stderr, "%s: cannot write %s: %s\n", argv[0], argv[1], image.message);
    return 1;
  }
  return 0;
}
