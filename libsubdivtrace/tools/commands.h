#pragma once
// The subcommands of the `subdivtrace` CLI. Each takes the arguments after its
// own name and returns the process exit code:
//   0 = ok, 1 = bad input (message on stderr naming the file and reason),
//   2 = usage error (message and the command's help on stderr).

#include <string>
#include <vector>

#include "render/view_args.h"

namespace subdivtrace::cli {

using Args = std::vector<std::string>;

int run_info(const Args& args);
int run_subdivide(const Args& args);
int run_export_mesh2(const Args& args);
int run_render(const Args& args);
int run_stats(const Args& args);
int run_stability(const Args& args);

/// Thrown by argument parsing; main prints it with the command's help, exit 2.
using UsageError = tools::UsageError;

}  // namespace subdivtrace::cli
