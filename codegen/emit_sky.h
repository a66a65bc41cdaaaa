/* Our fitted ground-level sky models (SPEC §7.2, models/hosek_sky_model.h):
 * the Hosek form (model "hosek", seed 000 eq. 35-37) and the Perez form
 * (model "preetham", seed 000 eq. 33) whose coefficients follow the sun
 * elevation as a quintic Bezier in (elevation / (pi/2))^(1/3), as emitted
 * code:
 *   vecN skyfit_hosek_sky_radiance(float mu, float mu_s, float nu)
 *   vecN skyfit_preetham_sky_radiance(float mu, float mu_s, float nu)
 * for a viewer on the ground: mu = cos(view zenith), mu_s = sin(sun
 * elevation), nu = cos(view-sun angle), SPEC §3. Inputs are clamped as the
 * model is valid: mu into [0, 1] (Hosek; its cos theta + 0.01 stays
 * finite) or [SF_SKY_PEREZ_MIN_MU, 1] (Perez divides by cos theta), nu
 * into what mu and mu_s allow; the elevation asin(mu_s) into [0, pi/2].
 * Then theta = acos(mu), gamma = acos(nu) and L = S F(theta, gamma) per
 * channel, S and the coefficients from the Bezier (models/hosek_bezier.h).
 * The constants are one const array per function: for each channel and
 * Bezier point, the coefficients then the scale. */
#ifndef SKYFIT_CODEGEN_EMIT_SKY_H
#define SKYFIT_CODEGEN_EMIT_SKY_H

#include "codegen/code_writer.h"
#include "models/hosek_sky_model.h"

#define SF_SKY_PEREZ_MIN_MU 1e-3

void sf_emit_sky(sf_code_writer *w, const sf_elevation_sky_model *m);

/* The clamps above in double for form's inputs (mu, mu_s, nu): the view
 * zenith angle theta, the view-sun angle gamma and the sun's elevation
 * asin(mu_s) (in [-pi/2, pi/2]; the forms take it into [0, pi/2]). */
void sf_sky_clamped_angles(sf_sky_form form, double mu, double mu_s, double nu, double *theta, double *gamma,
                           double *elevation);

/* The same clamps in double, then sf_elevation_sky_radiance, negative
 * radiance (the fitted forms dip below 0 near the horizon at a low sun)
 * raised to 0: what the emitted function approximates in float32. */
void sf_sky_radiance_clamped(const sf_elevation_sky_model *m, double mu, double mu_s, double nu,
                             double *radiance);

#endif
