#include "data/precompute_transmittance.h"

#include <math.h>
#include <string.h>

#include "data/gauss_rule.h"
#include "data/parallel_rows.h"
#include "data/ray_quadrature.h"
#include "models/optical_depth.h"
#include "models/ray_geometry.h"

/* Distance along (r, mu) to the end of the ray: the ground (the ray is
 * tangent to it or crosses it) or the top. */
static double ray_length(const sf_atmosphere *atm, double r, double mu, int to_ground) {
  double sphere = to_ground ? atm->bottom_radius_km : atm->top_radius_km;
  double t_near, t_far;
  if (!sf_ray_sphere_intersections(r, mu, sphere, &t_near, &t_far)) {
    /* A ground ray whose discriminant rounded below 0: it grazes the
     * ground at its closest approach. */
    return to_ground && mu < 0.0 ? -r * mu : 0.0;
  }
  if (to_ground) return t_near > 0.0 ? t_near : 0.0;
  return t_far > 0.0 ? t_far : 0.0;
}

void sf_transmittance_ray_depth(const sf_atmosphere *atm, double h, double mu, int to_ground,
                                double *depth) {
  sf_gauss_rule rule;
  sf_gauss_rule_init(&rule, SF_TRANSMITTANCE_NODES);
  double r = atm->bottom_radius_km + h;
  sf_ray_quad_optical_depth(atm, &rule, r, mu, 0.0, ray_length(atm, r, mu, to_ground), depth);
}

typedef struct transmittance_job {
  const sf_atmosphere *atm;
  const sf_table_params *p;
  sf_table *table;
  sf_gauss_rule rule;
} transmittance_job;

static void transmittance_row(void *ctx, int thread, long row) {
  (void)thread;
  const transmittance_job *job = ctx;
  const sf_atmosphere *atm = job->atm;
  const sf_table_desc *desc = &job->table->desc;
  int n0 = desc->axes[0].size;
  for (int i = 0; i < n0; ++i) {
    int index[2] = {i, (int)row};
    double pos[2] = {i, (double)row};
    double h, mu;
    sf_params_transmittance_coord(job->p, pos, &h, &mu);
    double r = atm->bottom_radius_km + h;
    int to_ground = job->p->kind == SF_PARAM_LEENMAN && sf_ray_hits_sphere_from_above(r, mu, atm->bottom_radius_km);
    double depth[SF_MAX_CONSTITUENTS], transmittance[SF_MAX_CHANNELS];
    sf_ray_quad_optical_depth(atm, &job->rule, r, mu, 0.0, ray_length(atm, r, mu, to_ground), depth);
    sf_transmittance_from_depth(atm, depth, transmittance);
    float *out = sf_table_at(job->table, index);
    for (int ch = 0; ch < atm->n_channels; ++ch) out[ch] = (float)transmittance[ch];
  }
}

int sf_precompute_transmittance(const sf_atmosphere *atm, const sf_table_params *p,
                                const sf_precompute_options *opt, sf_table *table, sf_error *err) {
  if (table->desc.n_axes != 2 || table->desc.n_channels != atm->n_channels)
    return sf_fail(err, SF_ERR_INTERNAL, "transmittance: table does not match the atmosphere");
  transmittance_job job = {atm, p, table, {0}};
  sf_gauss_rule_init(&job.rule, SF_TRANSMITTANCE_NODES);
  sf_parallel_rows(table->desc.axes[1].size, opt, "transmittance", transmittance_row, &job);
  return SF_OK;
}
