/* skyfit eval multiple_scattering | sky_radiance: quantities read from the
 * reference tables (data/sky_lookup.h). cli/cmd_eval.c hands these two
 * quantities over: sf_cmd_eval_tables takes the same argc/argv as
 * sf_cmd_eval (argv[0] = "eval"). */
#ifndef SKYFIT_CLI_CMD_EVAL_TABLES_H
#define SKYFIT_CLI_CMD_EVAL_TABLES_H

/* 1 if quantity is one that sf_cmd_eval_tables evaluates. */
int sf_eval_tables_handles(const char *quantity);

int sf_cmd_eval_tables(int argc, char **argv);

#endif
