/* The models of `skyfit fit MODEL` (SPEC §11). Each runs with argv[0] = the
 * model name and returns the exit code (0, 2 bad input, 1 internal). */
#ifndef SKYFIT_CLI_FIT_COMMANDS_H
#define SKYFIT_CLI_FIT_COMMANDS_H

typedef struct sf_fit_command {
  const char *model;
  int (*run)(int argc, char **argv);
  const char *summary;
} sf_fit_command;

/* Declared here, defined one per file as cli/cmd_fit_<model>.c. */
int sf_cmd_fit_sigmoid(int argc, char **argv);
int sf_cmd_fit_preetham(int argc, char **argv);
int sf_cmd_fit_hosek(int argc, char **argv);
int sf_cmd_fit_spectral4(int argc, char **argv);
int sf_cmd_fit_mlp_transmittance(int argc, char **argv);
int sf_cmd_fit_mlp_scattering(int argc, char **argv);
int sf_cmd_fit_mlp(int argc, char **argv);

#endif
