/* seed 000 (Leenman 2025) Appendix B and D, typed from the paper: the error
 * of each model against its path-traced (B) or 128-step raymarched (D)
 * reference, 1920x1080 images, exposures as models/views_standard.h; mean
 * squared errors, though headed RMSE (codegen/report.h says why). */
#include <math.h>
#include <string.h>

#include "codegen/report.h"

static const char *const b_columns[] = {"Preetham, Shirley, and Smits", "Empty", "Raymarched", "Schuler",
                                        "Naive", "Hillaire", "Neural Net", "Flat", "Bruneton and Neyret"};
static const char *const b_rows[] = {"ground-dawn", "ground-sunrise", "ground-noon", "plane-dawn",
                                     "plane-sunrise", "plane-noon", "orbit-dawn", "orbit-sunrise",
                                     "orbit-noon", "space", "planet-shadow-ground", "planet-shadow-orbit"};
static const double b_values[] = {
    3.97865605, 0.97482044, 0.00008048, 0.0002448, 0.00004764, 0.00003619, 0.00030104, 0.01105675, 0.00003364,
    0.00753167, 0.82744461, 0.00140716, 0.00094494, 0.00308942, 0.00109592, 0.02124281, 0.00176891, 0.00014694,
    0.00638251, 0.81927776, 0.00255514, 0.00589603, 0.00602361, 0.00009313, 0.00015921, 0.0026469, 0.00002464,
    3.95045567, 0.9558543, 0.00023158, 0.0008222, 0.00008869, 0.0000491, 0.00108281, 0.00202921, 0.0000453,
    0.03052294, 0.75808531, 0.00129824, 0.00113231, 0.00245048, 0.00011849, 0.00556002, 0.00116698, 0.0000506,
    0.02289433, 0.73097199, 0.00350788, 0.00615819, 0.00631668, 0.00007912, 0.00254121, 0.0036586, 0.00002183,
    4.08668518, 0.97941327, 0.00102501, 0.00645754, 0.00020258, 0.00003532, 0.01249882, 0.00992934, 0.00017324,
    0.04049467, 0.92837852, 0.00016845, 0.0005017, 0.00052833, 0.00002512, 0.00371327, 0.00070512, 0.00001186,
    0.02664175, 0.87550873, 0.00157611, 0.00226653, 0.00247161, 0.00001541, 0.0032039, 0.00149308, 0.00001374,
    0.03107663, 0.95405173, 0.00086303, 0.00104631, 0.00118762, 0.00001662, 0.00068834, 0.0013083, 0.00000733,
    2.65018225, 0.85214376, 0.00200995, 0.0040155, 0.00188857, 0.00032487, 0.00429041, 0.02545365, 0.00027963,
    2.96405864, 1.12555254, 0.00552621, 0.04436417, 0.01432145, 0.00023957, 0.21114185, 1.40199077, 0.00067625,
};

static const char *const d_columns[] = {"Neural network", "Flat"};
static const char *const d_rows[] = {"ground", "plane", "orbit", "space", "planet-shadow-orbit"};
static const double d_values[] = {
    0.00072169, 0.00018785,
    0.00577525, 0.00022608,
    0.00053684, 0.00010681,
    0.00011823, 0.00002235,
    0.00046473, 0.00009816,
};

void sf_paper_appendix_b(sf_paper_table *t) {
  t->n_columns = 9;
  t->n_rows = 12;
  t->columns = b_columns;
  t->rows = b_rows;
  t->values = b_values;
}

void sf_paper_appendix_d(sf_paper_table *t) {
  t->n_columns = 2;
  t->n_rows = 5;
  t->columns = d_columns;
  t->rows = d_rows;
  t->values = d_values;
}

int sf_paper_row(const sf_paper_table *t, const char *view_name) {
  for (int r = 0; r < t->n_rows; ++r)
    if (strcmp(t->rows[r], view_name) == 0) return r;
  return -1;
}

int sf_paper_column(const sf_paper_table *t, const char *column_name) {
  for (int c = 0; c < t->n_columns; ++c)
    if (strcmp(t->columns[c], column_name) == 0) return c;
  return -1;
}

double sf_paper_rmse(const sf_paper_table *t, int row, int column) {
  if (row < 0 || row >= t->n_rows || column < 0 || column >= t->n_columns) return NAN;
  return sqrt(t->values[row * t->n_columns + column]);
}

void sf_pareto_front(int n, const double *cost, const double *error, int *on_front) {
  for (int i = 0; i < n; ++i) {
    on_front[i] = 1;
    for (int j = 0; j < n && on_front[i]; ++j) {
      if (j == i) continue;
      if (cost[j] <= cost[i] && error[j] <= error[i] && (cost[j] < cost[i] || error[j] < error[i]))
        on_front[i] = 0;
    }
  }
}
