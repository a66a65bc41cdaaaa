/* skyfit build [SCENE.json] [--out DIR]: the whole pipeline (SPEC §11). */
#include "cli/build_command.h"
#include "cli/commands.h"

int sf_cmd_build(int argc, char **argv) { return sf_cli_build_or_report(argc, argv, 1, "skyfit build"); }
