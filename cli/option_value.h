/* An option's value on the command line, and the message for an argument
 * no option took. A value is the argument after its option unless that
 * argument is itself an option (begins with "--"): `--out --quiet` had
 * run a whole build into a folder named "--quiet", exit 0. A file whose
 * name begins with "--" is given as "./--name"; negative numbers ("-5")
 * are values. */
#ifndef SKYFIT_CLI_OPTION_VALUE_H
#define SKYFIT_CLI_OPTION_VALUE_H

/* argv[i + 1] as the value of option argv[i], or NULL where there is none
 * (past the end, or an option). */
const char *sf_cli_value_after(int argc, char **argv, int i);

/* Whether argument a is option name given with its value v (from
 * sf_cli_value_after). When a is name and v is NULL, *missing = name, for
 * sf_cli_bad_option's message; returns 0 then. */
int sf_cli_valued(const char *a, const char *name, const char *v, const char **missing);

/* For an argument a that no option took: "<command>: <missing> needs a
 * value; see --help" when missing is not NULL, else "<command>: unknown
 * option 'a'; see --help", on stderr. Returns 2 (bad input). */
int sf_cli_bad_option(const char *command, const char *a, const char *missing);

#endif
