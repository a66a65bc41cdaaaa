#include "fit/build_weights_errors.h"

#include <cjson/cJSON.h>

#include "models/weights_file.h"

static int record(const sf_report_model *m, sf_error *err) {
  const char *path = m->candidate->weights_path;
  sf_weights w;
  int status = sf_weights_load_file(path, NULL, &w, err);
  if (status != SF_OK) return status;
  cJSON *metrics = sf_weights_metrics(w.root);
  cJSON *e = cJSON_CreateObject();
  const sf_error_metrics *x = &m->errors;
  if (!metrics || !e || !cJSON_AddNumberToObject(e, "rmse", x->rmse) ||
      !cJSON_AddNumberToObject(e, "max_abs", x->max_abs) || !cJSON_AddNumberToObject(e, "mean_rel", x->mean_rel) ||
      !cJSON_AddNumberToObject(e, "rel_rmse", x->rel_rmse) ||
      !cJSON_AddNumberToObject(e, "values", (double)x->n_values) ||
      !cJSON_AddStringToObject(e, "over", m->errors_over_valid_part
                                              ? "the part of the scene's domain where the model applies"
                                              : "the scene's domain")) {
    cJSON_Delete(e);
    sf_weights_free(&w);
    return sf_fail(err, SF_ERR_INTERNAL, "%s: out of memory", path);
  }
  cJSON_DeleteItemFromObjectCaseSensitive(metrics, "build_error");
  cJSON_AddItemToObject(metrics, "build_error", e);
  status = sf_weights_write(w.root, path, err);
  sf_weights_free(&w);
  return status;
}

int sf_build_record_errors(const sf_report *rep, sf_error *err) {
  for (int k = 0; k < rep->n_models; ++k) {
    const sf_report_model *m = &rep->models[k];
    /* non-finite figures (a model that blew up) are left out: JSON has no
     * NaN, and the report states them */
    if (!m->has_errors || m->non_finite > 0 || !m->candidate->weights_path[0]) continue;
    int status = record(m, err);
    if (status != SF_OK) return status;
  }
  return SF_OK;
}
