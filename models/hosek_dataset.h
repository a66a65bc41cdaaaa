/* The published Hosek-Wilkie 2012 RGB coefficient dataset (version 1.4a
 * data, data/physical/hosek2012_rgb.json, described in
 * ../shared/data/hosek2012.md) and the sky state it yields for a turbidity,
 * ground albedo and sun elevation, computed exactly as the published code
 * (arhosekskymodel_cookconfiguration / cookradiance): quintic Bezier in
 * (elevation / (pi/2))^(1/3), bilinear in turbidity (integer table entries
 * 1..10) and albedo (tables for 0 and 1), the four terms summed in the
 * published order. Serves as a baseline and as the start of our fits. */
#ifndef SKYFIT_MODELS_HOSEK_DATASET_H
#define SKYFIT_MODELS_HOSEK_DATASET_H

#include "models/hosek.h"
#include "util/error.h"

#define SF_HOSEK_DATASET_CHANNELS 3
#define SF_HOSEK_DATASET_ALBEDOS 2
#define SF_HOSEK_DATASET_TURBIDITIES 10
#define SF_HOSEK_DATA_FILE "hosek2012_rgb.json"

typedef struct sf_hosek_dataset {
  char channel_names[SF_HOSEK_DATASET_CHANNELS][8];    /* "R", "G", "B" */
  /* In the file's STORAGE order (k = 7 is I, k = 8 is H), as published. */
  double coefficients[SF_HOSEK_DATASET_CHANNELS][SF_HOSEK_DATASET_ALBEDOS]
                     [SF_HOSEK_DATASET_TURBIDITIES][6][SF_HOSEK_N_COEFFS];
  double radiances[SF_HOSEK_DATASET_CHANNELS][SF_HOSEK_DATASET_ALBEDOS]
                  [SF_HOSEK_DATASET_TURBIDITIES][6];
} sf_hosek_dataset;

/* Loads and validates (shapes, finite numbers) a dataset file. */
int sf_hosek_dataset_load_file(const char *path, sf_hosek_dataset *out, sf_error *err);
/* The shipped file, found through util/data_path.h. */
int sf_hosek_dataset_load_default(sf_hosek_dataset *out, sf_error *err);

/* The state of one channel: coefficients in PAPER order A..I (H and I
 * swapped back from storage) and the radiance scale R. turbidity in
 * [1, 10], albedo in [0, 1], elevation in [0, pi/2] radians; outside:
 * SF_ERR_INPUT. */
int sf_hosek_dataset_state(const sf_hosek_dataset *d, int channel, double turbidity,
                           double albedo, double elevation_rad,
                           double coeffs[SF_HOSEK_N_COEFFS], double *radiance, sf_error *err);

/* The state's Bezier control points at one turbidity and albedo (the
 * blend of sf_hosek_dataset_state applied to the points, in paper order):
 * the quintic Bezier in x = (elevation / (pi/2))^(1/3) through them
 * (models/hosek_bezier.h) is the state at any elevation. Same checks. */
int sf_hosek_dataset_control_points(const sf_hosek_dataset *d, int channel, double turbidity, double albedo,
                                    double coeffs[6][SF_HOSEK_N_COEFFS], double radiance[6], sf_error *err);

/* Radiance of the published model: F(theta, gamma) R for one channel. */
double sf_hosek_dataset_radiance(const double coeffs[SF_HOSEK_N_COEFFS], double radiance_scale,
                                 double theta, double gamma);

#endif
