/* The sub-commands of `skyfit` (SPEC §11). Each returns the process exit
 * code: 0 success, 2 bad input, 1 internal failure. */
#ifndef SKYFIT_CLI_COMMANDS_H
#define SKYFIT_CLI_COMMANDS_H

int sf_cmd_eval(int argc, char **argv);
int sf_cmd_sample(int argc, char **argv);
int sf_cmd_fit(int argc, char **argv);
int sf_cmd_build(int argc, char **argv);
int sf_cmd_report(int argc, char **argv);
int sf_cmd_codegen(int argc, char **argv);

#endif
