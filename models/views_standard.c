#include "models/views_standard.h"

#include <math.h>
#include <stddef.h>

#include "util/constants.h"

#define DEG (SF_PI / 180.0)

/* seed 000 §11.4; field of view and pitch are ours (see the header): the
 * pitch of each place reproduces App. B's Empty column best
 * (bench/bench_views_calibration.c). */
#define PITCH_GROUND 3.0
#define PITCH_PLANE 9.0
#define PITCH_ORBIT -2.0

static const sf_view_def radiance_views[] = {
    {"ground-dawn", "Ground, dawn (sun -6°)", SF_PLACE_VIEWER, 0.0, PITCH_GROUND, 0.0, 60.0, -6.0, 0.0, 16.0},
    {"ground-sunrise", "Ground, sunrise (sun +6°)", SF_PLACE_VIEWER, 0.0, PITCH_GROUND, 0.0, 60.0, 6.0, 0.0, 1.0},
    {"ground-noon", "Ground, noon", SF_PLACE_VIEWER, 0.0, PITCH_GROUND, 0.0, 60.0, 90.0, 0.0, 1.0},
    {"plane-dawn", "Plane 5 km, dawn", SF_PLACE_VIEWER, 5.0, PITCH_PLANE, 0.0, 60.0, -6.0, 0.0, 16.0},
    {"plane-sunrise", "Plane 5 km, sunrise", SF_PLACE_VIEWER, 5.0, PITCH_PLANE, 0.0, 60.0, 6.0, 0.0, 1.0},
    {"plane-noon", "Plane 5 km, noon", SF_PLACE_VIEWER, 5.0, PITCH_PLANE, 0.0, 60.0, 90.0, 0.0, 1.0},
    {"orbit-dawn", "Orbit 100 km (1000 km back), dawn", SF_PLACE_VIEWER, 100.0, PITCH_ORBIT, 1000.0, 60.0, -6.0, 0.0, 16.0},
    {"orbit-sunrise", "Orbit, sunrise", SF_PLACE_VIEWER, 100.0, PITCH_ORBIT, 1000.0, 60.0, 6.0, 0.0, 1.0},
    {"orbit-noon", "Orbit, noon", SF_PLACE_VIEWER, 100.0, PITCH_ORBIT, 1000.0, 60.0, 90.0, 0.0, 1.0},
    {"space", "Space, sun top right", SF_PLACE_SPACE, 0.0, 0.0, 0.0, 40.0, 0.0, 0.0, 2.0},
    {"planet-shadow-ground", "Planet shadow from the ground (sun -3° right)", SF_PLACE_VIEWER, 0.0, PITCH_GROUND, 0.0, 60.0, -3.0, 90.0, 32.0},
    {"planet-shadow-orbit", "Planet shadow from 200 km (sun -3° right)", SF_PLACE_VIEWER, 200.0, NAN, 0.0, 60.0, -3.0, 90.0, 32.0},
};

static const sf_view_def transmittance_views[] = {
    {"ground", "Ground", SF_PLACE_VIEWER, 0.0, PITCH_GROUND, 0.0, 60.0, 90.0, 0.0, 1.0},
    {"plane", "Plane 5 km", SF_PLACE_VIEWER, 5.0, PITCH_PLANE, 0.0, 60.0, 90.0, 0.0, 1.0},
    {"orbit", "Orbit 100 km (1000 km back)", SF_PLACE_VIEWER, 100.0, PITCH_ORBIT, 1000.0, 60.0, 90.0, 0.0, 1.0},
    {"space", "Space", SF_PLACE_SPACE, 0.0, 0.0, 0.0, 40.0, 0.0, 0.0, 1.0},
    {"planet-shadow-orbit", "From 200 km", SF_PLACE_VIEWER, 200.0, NAN, 0.0, 60.0, -3.0, 90.0, 1.0},
};

int sf_standard_radiance_views(const sf_view_def **views) {
  *views = radiance_views;
  return (int)(sizeof radiance_views / sizeof radiance_views[0]);
}

int sf_standard_transmittance_views(const sf_view_def **views) {
  *views = transmittance_views;
  return (int)(sizeof transmittance_views / sizeof transmittance_views[0]);
}

static void normalize3(double v[3]) {
  double n = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  v[0] /= n;
  v[1] /= n;
  v[2] /= n;
}

static double dot3(const double a[3], const double b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

void sf_view_camera_make(const sf_view_def *v, const sf_atmosphere *atm, int width, int height,
                         sf_view_camera *cam) {
  const double R = atm->bottom_radius_km, Rt = atm->top_radius_km;
  cam->width = width;
  cam->height = height;
  cam->tan_half_v = tan(0.5 * v->vfov_deg * DEG);
  cam->tan_half_h = cam->tan_half_v * (double)width / (double)height;
  /* right = -y; up follows from forward and right. */
  cam->right[0] = 0.0;
  cam->right[1] = -1.0;
  cam->right[2] = 0.0;
  if (v->place == SF_PLACE_SPACE) {
    double distance = Rt / sin(0.8 * 0.5 * v->vfov_deg * DEG);
    cam->position[0] = -distance;
    cam->position[1] = 0.0;
    cam->position[2] = 0.0;
    cam->forward[0] = 1.0;
    cam->forward[1] = 0.0;
    cam->forward[2] = 0.0;
    cam->up[0] = 0.0;
    cam->up[1] = 0.0;
    cam->up[2] = 1.0;
    cam->sun[0] = 0.0;
    cam->sun[1] = -1.0 / sqrt(2.0);
    cam->sun[2] = 1.0 / sqrt(2.0);
    return;
  }
  double r0 = R + v->altitude_km;
  /* NAN pitch: down to the geometric horizon, cos(dip) = R / r. */
  double pitch = isnan(v->pitch_deg) ? -acos(R / r0) : v->pitch_deg * DEG;
  cam->forward[0] = cos(pitch);
  cam->forward[1] = 0.0;
  cam->forward[2] = sin(pitch);
  /* up = right x forward */
  cam->up[0] = -sin(pitch);
  cam->up[1] = 0.0;
  cam->up[2] = cos(pitch);
  for (int k = 0; k < 3; ++k) cam->position[k] = -v->move_back_km * cam->forward[k];
  cam->position[2] += r0;
  double e = v->sun_elevation_deg * DEG, a = v->sun_azimuth_deg * DEG;
  /* Azimuth from the horizontal forward (+x) towards the right (-y). */
  cam->sun[0] = cos(e) * cos(a);
  cam->sun[1] = -cos(e) * sin(a);
  cam->sun[2] = sin(e);
  normalize3(cam->sun);
}

void sf_view_pixel_direction(const sf_view_camera *cam, int i, int j, double d[3]) {
  double x = (2.0 * (i + 0.5) / cam->width - 1.0) * cam->tan_half_h;
  double y = (1.0 - 2.0 * (j + 0.5) / cam->height) * cam->tan_half_v;
  for (int k = 0; k < 3; ++k) d[k] = cam->forward[k] + x * cam->right[k] + y * cam->up[k];
  normalize3(d);
}

void sf_view_pixel_inputs(const sf_view_camera *cam, const sf_atmosphere *atm, int i, int j,
                          double in[4]) {
  double d[3];
  sf_view_pixel_direction(cam, i, j, d);
  double r = sqrt(dot3(cam->position, cam->position));
  double mu = dot3(cam->position, d) / r;
  double mu_s = dot3(cam->position, cam->sun) / r;
  double nu = dot3(d, cam->sun);
  in[0] = r - atm->bottom_radius_km;
  in[1] = fmax(-1.0, fmin(1.0, mu));
  in[2] = fmax(-1.0, fmin(1.0, mu_s));
  in[3] = fmax(-1.0, fmin(1.0, nu));
}

static unsigned char srgb8(double linear) {
  double x = linear > 0.0 ? (linear < 1.0 ? linear : 1.0) : 0.0;
  double s = x <= 0.0031308 ? 12.92 * x : 1.055 * pow(x, 1.0 / 2.4) - 0.055;
  return (unsigned char)lround(255.0 * s);
}

void sf_view_to_srgb8(const float *linear, size_t n, int tonemap, unsigned char *out) {
  for (size_t i = 0; i < 3 * n; ++i) {
    double x = isfinite(linear[i]) ? (double)linear[i] : 0.0;
    /* seed 000 §11.5: t(x) = 1 - exp(-x) */
    out[i] = srgb8(tonemap ? -expm1(-x) : x);
  }
}
