#include "fit/candidate.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int sf_candidate_n_inputs(sf_candidate_quantity q) {
  return q == SF_CANDIDATE_TRANSMITTANCE ? 2 : 4;
}

const char *sf_candidate_quantity_name(sf_candidate_quantity q) {
  return q == SF_CANDIDATE_TRANSMITTANCE ? "transmittance" : "sky_radiance";
}

const char *sf_candidate_role_name(sf_candidate_role r) {
  switch (r) {
    case SF_ROLE_REFERENCE: return "reference";
    case SF_ROLE_LOOKUP: return "lookup";
    case SF_ROLE_BASELINE: return "baseline";
    case SF_ROLE_FITTED: return "fitted";
  }
  return "?";
}

void sf_candidate_init(sf_candidate *c, sf_candidate_quantity q, sf_candidate_role role,
                       const char *name, const char *label) {
  memset(c, 0, sizeof *c);
  c->quantity = q;
  c->role = role;
  snprintf(c->name, sizeof c->name, "%s", name);
  snprintf(c->label, sizeof c->label, "%s", label);
  c->valid.h_min_km = 0.0;
  c->valid.h_max_km = 1e30;
  c->valid.mu_min = -1.0;
  c->valid.mu_max = 1.0;
  c->valid.mu_s_min = -1.0;
  c->valid.mu_s_max = 1.0;
}

void sf_candidate_free(sf_candidate *c) {
  if (c->free_ctx && c->ctx) c->free_ctx(c->ctx);
  memset(c, 0, sizeof *c);
}

int sf_candidate_valid_for(const sf_candidate *c, double h_km_clamped, double mu_s) {
  const double slack = 1e-9;
  return h_km_clamped >= c->valid.h_min_km - slack && h_km_clamped <= c->valid.h_max_km + slack &&
         mu_s >= c->valid.mu_s_min - slack && mu_s <= c->valid.mu_s_max + slack;
}

void sf_candidate_list_init(sf_candidate_list *l) { memset(l, 0, sizeof *l); }

int sf_candidate_list_add(sf_candidate_list *l, sf_candidate *c) {
  if (l->count == l->capacity) {
    int cap = l->capacity ? 2 * l->capacity : 8;
    sf_candidate *grown = realloc(l->items, sizeof *grown * (size_t)cap);
    if (!grown) {
      sf_candidate_free(c);
      return -1;
    }
    l->items = grown;
    l->capacity = cap;
  }
  l->items[l->count++] = *c;
  memset(c, 0, sizeof *c);
  return 0;
}

void sf_candidate_list_free(sf_candidate_list *l) {
  for (int i = 0; i < l->count; ++i) sf_candidate_free(&l->items[i]);
  free(l->items);
  memset(l, 0, sizeof *l);
}

int sf_candidate_list_find(const sf_candidate_list *l, sf_candidate_quantity q, const char *name) {
  for (int i = 0; i < l->count; ++i)
    if (l->items[i].quantity == q && strcmp(l->items[i].name, name) == 0) return i;
  return -1;
}
