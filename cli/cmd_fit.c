/* skyfit fit MODEL: dispatch to the model's fitter (SPEC §7, §11). */
#include <stdio.h>
#include <string.h>

#include "cli/commands.h"
#include "cli/fit_commands.h"

/* One line per model whose fitter exists. */
static const sf_fit_command fit_commands[] = {
    {"sigmoid", sf_cmd_fit_sigmoid, "sigmoid-polynomial transmittance per constituent and channel (SPEC 7.1)"},
    {"preetham", sf_cmd_fit_preetham, "Perez/Preetham sky K F(theta,gamma) over the sun range (SPEC 7.2)"},
    {"hosek", sf_cmd_fit_hosek, "Hosek-Wilkie 2012 sky F(theta,gamma) R over the sun range (SPEC 7.2)"},
    {"spectral4", sf_cmd_fit_spectral4, "4 wavelengths + weights for spectral rendering at RGB cost (SPEC 7.3)"},
    {"mlp-transmittance", sf_cmd_fit_mlp_transmittance, "transmittance MLP (seed 000 §9.6.1), hand-written Adam"},
    {"mlp-scattering", sf_cmd_fit_mlp_scattering, "scattering MLP (seed 000 §9.6.2), exp(-x) outputs"},
    {"mlp", sf_cmd_fit_mlp, "an MLP on any CSV (--dump-dataset), for trainer comparisons"},
    {NULL, NULL, NULL},
};

static void fit_usage(FILE *out) {
  fprintf(out,
          "usage: skyfit fit MODEL [options]\n"
          "\n"
          "Fits a compact model to the reference data and writes its weights file (SPEC §8).\n"
          "\n"
          "models:\n");
  for (const sf_fit_command *c = fit_commands; c->model; ++c)
    fprintf(out, "  %-18s %s\n", c->model, c->summary);
  fprintf(out, "\n'skyfit fit MODEL --help' describes the model's options.\n");
}

int sf_cmd_fit(int argc, char **argv) {
  if (argc < 2) {
    fit_usage(stderr);
    return 2;
  }
  if (strcmp(argv[1], "--help") == 0 || strcmp(argv[1], "-h") == 0) {
    fit_usage(stdout);
    return 0;
  }
  for (const sf_fit_command *c = fit_commands; c->model; ++c)
    if (strcmp(argv[1], c->model) == 0) return c->run(argc - 1, argv + 1);
  fprintf(stderr, "skyfit fit: unknown model '%s'\n", argv[1]);
  fit_usage(stderr);
  return 2;
}
