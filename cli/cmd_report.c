/* skyfit report [SCENE.json] [--out DIR]: the report stage (SPEC §12). */
#include "cli/build_command.h"
#include "cli/commands.h"

int sf_cmd_report(int argc, char **argv) { return sf_cli_build_or_report(argc, argv, 0, "skyfit report"); }
