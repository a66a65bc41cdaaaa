/* The report's standard views (SPEC §12; codegen/report.h): pictures of the
 * reference and of every model of each quantity, compared pixel by pixel.
 *
 * A pixel is compared where both pictures hold data. Its ray starts at the
 * viewer or, for a viewer above the top, where it enters the atmosphere
 * (data/sky_lookup.h); the start must lie in the model's valid box (Hosek:
 * a viewer on the ground looking up, the sun up) and, for sky radiance, in
 * the scene's domain, the only part the reference tables cover. Below the
 * domain they are extrapolated: an above-horizon scene's ground view had
 * been scored on a made-up bright ground, and Preetham on the ground
 * pixels it does not model. A ray that never enters the atmosphere
 * (radiance 0, transmittance 1) is compared where the viewer, moved down
 * to the top, lies in the box. Pixels a picture has
 * no data for are black in it and 0 in the error map; each view records
 * the share of its pixels compared, and a view with none is not rendered
 * for that model. */
#ifndef SKYFIT_CODEGEN_REPORT_VIEWS_H
#define SKYFIT_CODEGEN_REPORT_VIEWS_H

#include "codegen/report.h"

/* Renders the views of every quantity rep measures into rep->out_dir/views
 * and fills each model's views[]; RGB atmospheres only. */
int sf_report_render_views(sf_report *rep, const sf_scene *scene, const sf_report_options *o, sf_error *err);

/* Removes from out_dir/views the pictures and error maps an earlier run
 * left that rep does not name (another scene's views, a model this run did
 * not have), and from out_dir/plots the plot of a quantity rep does not
 * plot, so the folders show this report alone. Only names a report writes
 * are touched: "transmittance-" or "sky_radiance-" followed by anything
 * ending in ".png" or ".exr", and "<quantity>-cost-error.svg". *n_removed
 * counts them; on a failure the rest are still tried and err names the
 * first. */
int sf_report_remove_stale_pictures(const sf_report *rep, const char *out_dir, int *n_removed, sf_error *err);

#endif
