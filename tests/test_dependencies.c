/* The four Debian libraries of SPEC §2 are found, linked and callable from C:
 * Ceres (C API) recovers a known exponential, NLopt's Nelder-Mead finds the
 * Rosenbrock minimum, cJSON and OpenEXR report themselves. Later fitters
 * stand on this glue. */
#include <ceres/c_api.h>
#include <cjson/cJSON.h>
#include <nlopt.h>
#include <OpenEXR/openexr.h>

#include "check.h"

/* residual_i = y_i - exp(m x_i + c) for the parameter block (m, c) */
typedef struct sample { double x, y; } sample;

static int exponential_residual(void *user, double **parameters, double *residual, double **jacobians) {
  const sample *s = user;
  double m = parameters[0][0], c = parameters[0][1];
  double model = exp(m * s->x + c);
  residual[0] = s->y - model;
  if (jacobians && jacobians[0]) {
    jacobians[0][0] = -s->x * model;
    jacobians[0][1] = -model;
  }
  return 1;
}

static double rosenbrock(unsigned n, const double *x, double *grad, void *data) {
  (void)n, (void)grad, (void)data;
  return 100.0 * (x[1] - x[0] * x[0]) * (x[1] - x[0] * x[0]) + (1.0 - x[0]) * (1.0 - x[0]);
}

int main(void) {
  printf("-- Ceres C API: recover y = exp(0.3 x + 0.1) from exact samples\n");
  ceres_init();
  enum { N = 40 };
  sample data[N];
  for (int i = 0; i < N; ++i) {
    data[i].x = 0.1 * i;
    data[i].y = exp(0.3 * data[i].x + 0.1);
  }
  double mc[2] = {0.0, 0.0};
  double *blocks[1] = {mc};
  int sizes[1] = {2};
  ceres_problem_t *problem = ceres_create_problem();
  for (int i = 0; i < N; ++i)
    ceres_problem_add_residual_block(problem, exponential_residual, &data[i], NULL, NULL, 1, 1, sizes, blocks);
  ceres_solve(problem);
  ceres_free_problem(problem);
  CHECK_ABS(mc[0], 0.3, 1e-9);
  CHECK_ABS(mc[1], 0.1, 1e-9);

  printf("-- NLopt Nelder-Mead: Rosenbrock minimum at (1, 1)\n");
  nlopt_opt opt = nlopt_create(NLOPT_LN_NELDERMEAD, 2);
  nlopt_set_min_objective(opt, rosenbrock, NULL);
  nlopt_set_xtol_rel(opt, 1e-12);
  nlopt_set_maxeval(opt, 20000);
  double x[2] = {-1.2, 1.0}, fmin = 0.0;
  nlopt_result r = nlopt_optimize(opt, x, &fmin);
  nlopt_destroy(opt);
  CHECK(r > 0);
  CHECK_ABS(x[0], 1.0, 1e-6);
  CHECK_ABS(x[1], 1.0, 1e-6);

  printf("-- cJSON and OpenEXR versions\n");
  cJSON *doc = cJSON_Parse("{\"g\": 0.8}");
  CHECK(doc && cJSON_GetObjectItemCaseSensitive(doc, "g")->valuedouble == 0.8);
  cJSON_Delete(doc);
  int major = 0, minor = 0, patch = 0;
  const char *extra = NULL;
  exr_get_library_version(&major, &minor, &patch, &extra);
  printf("cJSON %s, OpenEXR %d.%d.%d\n", cJSON_Version(), major, minor, patch);
  CHECK(major >= 3);
  return check_summary();
}
