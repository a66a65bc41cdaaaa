/* skyfit: command dispatch (SPEC §11). */
#include <stdio.h>
#include <string.h>

#include "cli/commands.h"
#include "cli/output_file_check.h"

typedef struct command {
  const char *name;
  int (*run)(int argc, char **argv);
  const char *summary;
} command;

static const command commands[] = {
    {"build", sf_cmd_build, "the whole pipeline for a scene: sample, fit, select, emit GLSL and C, report"},
    {"report", sf_cmd_report, "measure every model of a scene and write report.html, report.md, metrics.json"},
    {"codegen", sf_cmd_codegen, "emit GLSL and C headers for fitted models and analytic baselines"},
    {"eval", sf_cmd_eval,
     "evaluate at CSV points the reference quantities (optical depth ... sky radiance) or a fitted model"},
    {"fit", sf_cmd_fit, "fit a compact model (sigmoid, preetham, hosek, spectral4, mlp-*) and write its weights"},
    {"sample", sf_cmd_sample, "compute the reference tables (transmittance, single and multiple scattering) into a folder"},
};

static void usage(FILE *out) {
  fprintf(out,
          "usage: skyfit <command> [options]\n"
          "\n"
          "skyfit turns a physical description of an atmosphere into small, fast sky models.\n"
          "\n"
          "commands:\n");
  for (size_t i = 0; i < sizeof commands / sizeof commands[0]; ++i)
    fprintf(out, "  %-10s %s\n", commands[i].name, commands[i].summary);
  fprintf(out, "\n'skyfit <command> --help' describes a command's options.\n");
}

/* A command that succeeded but whose stdout could not be written (a help
 * text to a full disk had exited 0) exits 1. */
static int finished(int status) {
  if (status == 0 && sf_cli_stdout_written("skyfit")) return 1;
  return status;
}

int main(int argc, char **argv) {
  if (argc < 2) {
    usage(stderr);
    return 2;
  }
  if (strcmp(argv[1], "--help") == 0 || strcmp(argv[1], "-h") == 0 || strcmp(argv[1], "help") == 0) {
    usage(stdout);
    return finished(0);
  }
  if (strcmp(argv[1], "--version") == 0) {
    printf("skyfit %s\n", SKYFIT_VERSION);
    return finished(0);
  }
  for (size_t i = 0; i < sizeof commands / sizeof commands[0]; ++i)
    if (strcmp(argv[1], commands[i].name) == 0) return finished(commands[i].run(argc - 1, argv + 1));
  fprintf(stderr, "skyfit: unknown command '%s'\n", argv[1]);
  usage(stderr);
  return 2;
}
