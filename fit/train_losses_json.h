/* The training losses in a weights file's metrics (SPEC §8).
 *
 * A sky split at the horizon has two networks, and the sky network may
 * train on targets divided by the fitted brightness (fit/output_norm.h)
 * while the ground network's are raw radiance: their losses are in
 * different units. So each network's losses are written apart, with the
 * units of its targets, never averaged into one figure:
 *   "train_loss", "validation_loss", "loss_targets"    the sky network (or the only one)
 *   "ground_network": {the same three}                 the ground network of a split sky
 * "loss_targets" is "raw", "brightness_normalised" or, for a transmittance
 * network trained on the k-th roots of its targets (fit/target_root.h),
 * "root_<k>" (the ground network's are raw); a validation loss
 * that is not finite (no validation set) is left out. */
#ifndef SKYFIT_FIT_TRAIN_LOSSES_JSON_H
#define SKYFIT_FIT_TRAIN_LOSSES_JSON_H

#include <cjson/cJSON.h>

#include "fit/train.h"

/* ground: NULL without a split. 0, or -1 when out of memory. */
/* sky_normalised: the sky network's targets brightness-normalised; else
 * sky_target_root (1: raw) names their units (fit/target_root.h). */
int sf_train_losses_to_json(cJSON *metrics, const sf_train_result *sky, int sky_normalised, int sky_target_root,
                            const sf_train_result *ground);

#endif
