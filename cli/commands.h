#pragma once
// The subcommands: each registers its options on the app and returns the function that runs it.

#include <functional>
#include <vector>

#include <CLI/CLI.hpp>

#include "cli/shard.h"

namespace exao::cli {

/// Runs the command if it was parsed (its exit status), else returns -1.
using Command = std::function<int(const Invocation&)>;

Command add_render_command(CLI::App& app);
Command add_info_command(CLI::App& app);
Command add_bench_command(CLI::App& app);
Command add_query_command(CLI::App& app);
Command add_bake_command(CLI::App& app);
Command add_compare_command(CLI::App& app);

/// Every subcommand on `app` (main, and exao merge re-running a recorded command).
std::vector<Command> register_commands(CLI::App& app);

}  // namespace exao::cli
