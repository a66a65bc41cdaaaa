/* The reference check (data/sky_table_check.h) in words. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "codegen/report.h"
#include "util/str_append.h"

void sf_report_reference_check_text(const sf_report *rep, char *buf, size_t n) {
  static const char *const band_names[SF_SKY_CHECK_BANDS] = {"sun above 5.7 deg", "0 to 5.7 deg", "0 to -5.7 deg",
                                                             "below -5.7 deg"};
  const sf_sky_table_check *c = &rep->reference_check;
  if (n) buf[0] = '\0';
  if (!c->present) return;
  sf_str_append(buf, n,
                "Reference check: the tables' single scattering (phases applied) against direct integration "
                "(models/single_scattering.h) at %zu points of the domain", c->n_points);
  if (c->n_outside) sf_str_append(buf, n, " (%zu more, whose rays miss the atmosphere, have no sky)", c->n_outside);
  sf_str_append(buf, n, ": ");
  if (isfinite(c->rel_rmse))
    sf_str_append(buf, n, "relative RMSE %.3g %%", 100.0 * c->rel_rmse);
  else
    sf_str_append(buf, n, "RMSE %.3g (the direct single scattering is 0 at every point)", c->rmse);
  int listed = 0;
  for (int b = 0; b < SF_SKY_CHECK_BANDS; ++b) {
    if (c->band[b].n_points == 0 || !isfinite(c->band[b].rel_rmse)) continue;
    sf_str_append(buf, n, "%s%s: %.3g %% (%zu points)", listed++ ? "; " : " (", band_names[b],
                  100.0 * c->band[b].rel_rmse, c->band[b].n_points);
  }
  if (listed) sf_str_append(buf, n, ")");
  /* no largest error where table and direct agree everywhere (an
   * atmosphere that only absorbs: both 0): it had named a point and an
   * empty channel */
  if (!(c->max_abs == 0.0))
    sf_str_append(buf, n, ", largest error %.3g (table %.4g, direct %.4g) at h %.4g km, mu %.4g, mu_s %.4g, nu %.4g, "
                  "channel %s", c->max_abs, c->worst_table, c->worst_direct, c->worst_h_km, c->worst_mu,
                  c->worst_mu_s, c->worst_nu, c->worst_channel_name);
  else
    sf_str_append(buf, n, ", equal at every point");
  sf_str_append(buf, n,
                ". The models' errors above are measured against these tables. Multiple scattering, checked "
                "against the path tracer at chosen points by the tests only, is %.3g %% of the sky radiance's "
                "RMS here.",
                100.0 * c->multiple_share);
}
