#pragma once
// The subcommands: each registers its options on the app and returns the function that runs it.

#include <functional>

#include <CLI/CLI.hpp>

namespace exao::cli {

using Command = std::function<int()>;

Command add_render_command(CLI::App& app);
Command add_info_command(CLI::App& app);
Command add_bench_command(CLI::App& app);
Command add_query_command(CLI::App& app);
Command add_bake_command(CLI::App& app);
Command add_compare_command(CLI::App& app);

}  // namespace exao::cli
