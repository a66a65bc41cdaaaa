/* The canonical text of an atmosphere: one JSON rendering per struct (fixed
 * key order, %.17g numbers so every double survives the round trip, every
 * field explicit), and its FNV-1a hash. One writer feeds either a growing
 * buffer or the hash, so hashing never allocates. */
#include "models/atmosphere_file.h"

#include <inttypes.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "models/phase.h"
#include "util/hash64.h"

typedef struct json_sink {
  int collect;       /* 1: append to text; 0: only update hash */
  char *text;
  size_t len, cap;
  int out_of_memory;
  uint64_t hash;
} json_sink;

static void emit_bytes(json_sink *s, const char *p, size_t n) {
  if (!s->collect) {
    s->hash = sf_fnv1a64(s->hash, p, n);
    return;
  }
  if (s->out_of_memory) return;
  if (s->len + n + 1 > s->cap) {
    size_t cap = s->cap ? s->cap : 4096;
    while (s->len + n + 1 > cap) cap *= 2;
    char *grown = realloc(s->text, cap);
    if (!grown) {
      s->out_of_memory = 1;
      return;
    }
    s->text = grown;
    s->cap = cap;
  }
  memcpy(s->text + s->len, p, n);
  s->len += n;
  s->text[s->len] = '\0';
}

static void emit(json_sink *s, const char *text) { emit_bytes(s, text, strlen(text)); }

static void emit_number(json_sink *s, double x) {
  char buf[40];
  /* A hand-built struct may hold what JSON cannot; null makes loading it
   * fail with a clear type error instead of producing invalid JSON. */
  if (!isfinite(x)) snprintf(buf, sizeof buf, "null");
  else snprintf(buf, sizeof buf, "%.17g", x);
  emit(s, buf);
}

static void emit_string(json_sink *s, const char *str, size_t max_len) {
  size_t n = strnlen(str, max_len);
  emit(s, "\"");
  for (size_t i = 0; i < n; ++i) {
    unsigned char ch = (unsigned char)str[i];
    char buf[8];
    if (ch == '"' || ch == '\\') {
      buf[0] = '\\';
      buf[1] = (char)ch;
      emit_bytes(s, buf, 2);
    } else if (ch < 0x20) {
      snprintf(buf, sizeof buf, "\\u%04x", ch);
      emit(s, buf);
    } else {
      emit_bytes(s, (const char *)&ch, 1);
    }
  }
  emit(s, "\"");
}

static void emit_array(json_sink *s, const double *v, int n) {
  emit(s, "[");
  for (int i = 0; i < n; ++i) {
    if (i) emit(s, ", ");
    emit_number(s, v[i]);
  }
  emit(s, "]");
}

static void emit_key_number(json_sink *s, const char *key_text, double x) {
  emit(s, key_text);
  emit_number(s, x);
}

static void emit_phase(json_sink *s, const sf_phase *p) {
  const char *kind = sf_phase_kind_name(p->kind);
  emit(s, "{\"kind\": ");
  emit_string(s, kind ? kind : "invalid", 64);
  switch (p->kind) {
    case SF_PHASE_HENYEY_GREENSTEIN:
    case SF_PHASE_CORNETTE_SHANKS:
      emit_key_number(s, ", \"g\": ", p->g);
      break;
    case SF_PHASE_DOUBLE_HENYEY_GREENSTEIN:
      emit_key_number(s, ", \"g1\": ", p->g1);
      emit_key_number(s, ", \"g2\": ", p->g2);
      emit_key_number(s, ", \"f\": ", p->f);
      break;
    default:
      break;
  }
  emit(s, "}");
}

static void emit_constituent(json_sink *s, const sf_constituent *c, int n_channels) {
  emit(s, "    {\n      \"name\": ");
  emit_string(s, c->name, sizeof c->name);
  emit(s, ",\n      \"scattering\": ");
  emit_array(s, c->scattering, n_channels);
  emit(s, ",\n      \"absorption\": ");
  emit_array(s, c->absorption, n_channels);
  if (c->phase.kind != SF_PHASE_NONE) {
    emit(s, ",\n      \"phase\": ");
    emit_phase(s, &c->phase);
  }
  emit(s, ",\n      \"density\": [\n");
  for (int j = 0; j < c->n_layers; ++j) {
    const sf_density_layer *l = &c->layers[j];
    emit_key_number(s, "        {\"width_km\": ", l->width_km);
    emit_key_number(s, ", \"exp_term\": ", l->exp_term);
    emit_key_number(s, ", \"exp_scale_per_km\": ", l->exp_scale_per_km);
    emit_key_number(s, ", \"linear_per_km\": ", l->linear_per_km);
    emit_key_number(s, ", \"constant\": ", l->constant);
    emit(s, j + 1 < c->n_layers ? "},\n" : "}\n");
  }
  emit(s, "      ]\n    }");
}

static void emit_atmosphere(json_sink *s, const sf_atmosphere *atm) {
  emit(s, "{\n  \"name\": ");
  emit_string(s, atm->name, sizeof atm->name);
  emit_key_number(s, ",\n  \"bottom_radius_km\": ", atm->bottom_radius_km);
  emit_key_number(s, ",\n  \"top_radius_km\": ", atm->top_radius_km);
  emit(s, ",\n  \"channels\": ");
  if (atm->spectral) {
    emit(s, "{\"wavelengths_nm\": ");
    emit_array(s, atm->wavelengths_nm, atm->n_channels);
    emit(s, "}");
  } else {
    emit(s, "\"rgb\"");
  }
  emit(s, ",\n  \"ground_albedo\": ");
  emit_array(s, atm->ground_albedo, atm->n_channels);
  emit(s, ",\n  \"sun_irradiance\": ");
  emit_array(s, atm->sun_irradiance, atm->n_channels);
  emit_key_number(s, ",\n  \"sun_angular_radius_rad\": ", atm->sun_angular_radius_rad);
  emit(s, ",\n  \"constituents\": [\n");
  for (int i = 0; i < atm->n_constituents; ++i) {
    emit_constituent(s, &atm->constituents[i], atm->n_channels);
    emit(s, i + 1 < atm->n_constituents ? ",\n" : "\n");
  }
  emit(s, "  ]\n}\n");
}

char *sf_atmosphere_to_json(const sf_atmosphere *atm) {
  json_sink s = {1, NULL, 0, 0, 0, 0};
  emit_atmosphere(&s, atm);
  if (s.out_of_memory) {
    free(s.text);
    return NULL;
  }
  return s.text;
}

uint64_t sf_atmosphere_hash(const sf_atmosphere *atm) {
  json_sink s = {0, NULL, 0, 0, 0, SF_FNV1A64_OFFSET};
  emit_atmosphere(&s, atm);
  return s.hash;
}

void sf_atmosphere_hash_hex(const sf_atmosphere *atm, char out[17]) {
  snprintf(out, 17, "%016" PRIx64, sf_atmosphere_hash(atm));
}
