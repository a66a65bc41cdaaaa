/* The shared front end of `skyfit build` and `skyfit report` (SPEC §11):
 * options, scene loading, progress, the closing lines. build also fits and
 * emits; report measures and reports the candidates without emitting. */
#ifndef SKYFIT_CLI_BUILD_COMMAND_H
#define SKYFIT_CLI_BUILD_COMMAND_H

int sf_cli_build_or_report(int argc, char **argv, int emit, const char *command);

#endif
