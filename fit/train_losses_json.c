#include "fit/train_losses_json.h"

#include <math.h>

#include "fit/target_root.h"

static int add_losses(cJSON *obj, const sf_train_result *r, const char *targets) {
  if (!cJSON_AddNumberToObject(obj, "train_loss", r->train_loss)) return -1;
  if (isfinite(r->validation_loss) && !cJSON_AddNumberToObject(obj, "validation_loss", r->validation_loss)) return -1;
  return cJSON_AddStringToObject(obj, "loss_targets", targets) ? 0 : -1;
}

int sf_train_losses_to_json(cJSON *metrics, const sf_train_result *sky, int sky_normalised, int sky_target_root,
                            const sf_train_result *ground) {
  char root[32];
  sf_target_root_label(sky_target_root, root, sizeof root);
  if (add_losses(metrics, sky, sky_normalised ? "brightness_normalised" : root)) return -1;
  if (!ground) return 0;
  cJSON *g = cJSON_AddObjectToObject(metrics, "ground_network");
  return g ? add_losses(g, ground, "raw") : -1;
}
