#include "cli/table_options.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cli/atmosphere_warnings.h"
#include "cli/option_value.h"
#include "models/atmosphere_file.h"
#include "models/scene_file.h"

void sf_table_cli_default(sf_table_cli *o) {
  memset(o, 0, sizeof *o);
  sf_table_set_options_default(&o->set);
}

static int parse_int(const char *text, long lo, long hi, long *out) {
  char *end;
  errno = 0;
  long v = strtol(text, &end, 10);
  if (end == text || *end != '\0' || errno == ERANGE || v < lo || v > hi) return -1;
  *out = v;
  return 0;
}

int sf_table_cli_option(sf_table_cli *o, const char *command, int argc, char **argv, int *i) {
  const char *a = argv[*i];
  const char *v = sf_cli_value_after(argc, argv, *i);
  int has_value = v != NULL;
  sf_error err = {0};
  if (strcmp(a, "--quiet") == 0) {
    o->quiet = 1;
    return 1;
  }
  static const char *const with_value[] = {"--atmosphere", "--scene", "--resolution", "--orders", "--stop-fraction",
                                           "--parameterization", "--threads", NULL};
  int known = 0;
  for (int k = 0; with_value[k]; ++k) known |= strcmp(a, with_value[k]) == 0;
  if (!known) return 0;
  if (!has_value) {
    sf_cli_bad_option(command, a, a);
    return -1;
  }
  ++*i;
  long n;
  if (strcmp(a, "--atmosphere") == 0) {
    o->atmosphere_path = v;
  } else if (strcmp(a, "--scene") == 0) {
    o->scene_path = v;
  } else if (strcmp(a, "--resolution") == 0) {
    if (sf_table_resolution_parse(v, &o->set.res, &err) != SF_OK) {
      fprintf(stderr, "%s: %s\n", command, err.message);
      return -1;
    }
  } else if (strcmp(a, "--orders") == 0) {
    if (parse_int(v, 1, SF_MULTIPLE_MAX_ORDERS, &n)) {
      fprintf(stderr, "%s: --orders: expected a whole number of scattering orders in 1..%d, got '%s'\n",
              command, SF_MULTIPLE_MAX_ORDERS, v);
      return -1;
    }
    o->set.orders = (int)n;
  } else if (strcmp(a, "--stop-fraction") == 0) {
    char *end;
    double f = strtod(v, &end);
    if (end == v || *end != '\0' || !(f >= 0.0 && f < 1.0)) {
      fprintf(stderr, "%s: --stop-fraction: expected a fraction in [0, 1), got '%s'\n", command, v);
      return -1;
    }
    o->set.stop_fraction = f;
  } else if (strcmp(a, "--parameterization") == 0) {
    if (sf_parameterization_parse(v, &o->set.kind, &err) != SF_OK) {
      fprintf(stderr, "%s: --%s\n", command, err.message);
      return -1;
    }
  } else if (strcmp(a, "--threads") == 0) {
    if (parse_int(v, 1, 4096, &n)) {
      fprintf(stderr, "%s: --threads: expected a whole number in 1..4096, got '%s'\n", command, v);
      return -1;
    }
    o->set.run.n_threads = (int)n;
  }
  return 1;
}

void sf_table_cli_help(FILE *out) {
  fprintf(out,
          "  --atmosphere FILE       atmosphere JSON (default: the built-in Earth, SPEC §4)\n"
          "  --scene FILE            scene JSON (SPEC §5): its atmosphere, and scattering tables\n"
          "                          over its domain only (viewer altitudes, view and sun angles);\n"
          "                          transmittance alone if that is all it asks for. Not with\n"
          "                          --atmosphere (the scene names its atmosphere)\n"
          "  --parameterization P    bruneton (default; horizon-aware, Bruneton 2017) or leenman\n"
          "                          (seed 000 §9.1: h = H x^2, cosines linear, 4D tiled into 2D)\n"
          "  --resolution T,S        sample counts: transmittance MUxH, then scattering\n"
          "                          HxMUxMU_SxNU (default 256x64,32x128x32x8)\n"
          "  --orders N              highest scattering order, 1..%d (default %d; 1: single only)\n"
          "  --stop-fraction F       stop once the orders left would add less than F of the sky\n"
          "                          radiance so far in every channel (a geometric tail of the\n"
          "                          last two; default %g: all orders, 7 for Earth; 0: always N)\n"
          "  --threads N             worker threads (default: all cores); results do not depend on it\n"
          "  --quiet                 no progress bar or notes\n",
          SF_MULTIPLE_MAX_ORDERS, SF_TABLE_SET_DEFAULT_ORDERS, SF_TABLE_SET_DEFAULT_STOP_FRACTION);
}

/* The scene's atmosphere, domain and quantities into atm and o->set. */
static int apply_scene(sf_table_cli *o, const char *command, sf_atmosphere *atm) {
  sf_scene *scene = malloc(sizeof *scene);   /* large: holds an atmosphere */
  if (!scene) {
    fprintf(stderr, "%s: out of memory\n", command);
    return 1;
  }
  sf_error err = {0};
  sf_scene_domain d;
  if (sf_scene_load_file(o->scene_path, scene, &err) != SF_OK ||
      sf_scene_get_domain(scene, &d, &err) != SF_OK) {
    fprintf(stderr, "%s: %s\n", command, err.message);
    free(scene);
    return err.status ? err.status : 2;
  }
  sf_cli_warn_atmosphere_units(command, scene->atmosphere_path, &scene->atmosphere);
  *atm = scene->atmosphere;
  o->scene_domain = d;
  o->set.has_domain = 1;
  o->set.domain.h_min_km = d.h_min_km;
  o->set.domain.h_max_km = d.h_max_km;
  o->set.domain.mu_min = d.mu_min;
  o->set.domain.mu_s_min = d.mu_s_min;
  o->set.domain.mu_s_max = d.mu_s_max;
  o->set.domain.sky_only = scene->view == SF_VIEW_ABOVE_HORIZON;
  o->set.transmittance_only = !(scene->quantities & SF_QUANTITY_SKY_RADIANCE);
  free(scene);
  return 0;
}

int sf_table_cli_atmosphere(sf_table_cli *o, const char *command, sf_atmosphere *atm) {
  if (o->scene_path && o->atmosphere_path) {
    fprintf(stderr,
            "%s: --atmosphere and --scene both choose the atmosphere; give one (a scene names its "
            "atmosphere with its \"atmosphere\" key)\n", command);
    return 2;
  }
  if (o->scene_path) return apply_scene(o, command, atm);
  if (!o->atmosphere_path) {
    sf_atmosphere_default(atm);
    return 0;
  }
  sf_error err = {0};
  if (sf_atmosphere_load_file(o->atmosphere_path, atm, &err) != SF_OK) {
    fprintf(stderr, "%s: %s\n", command, err.message);
    return err.status ? err.status : 2;
  }
  sf_cli_warn_atmosphere_units(command, o->atmosphere_path, atm);
  return 0;
}
