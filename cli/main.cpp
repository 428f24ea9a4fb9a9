// exao: exact ray-cast ambient occlusion. See README.md for every subcommand.

#include <csignal>
#include <vector>

#include <unistd.h>

#include <CLI/CLI.hpp>

#include "cli/commands.h"
#include "core/atomic_write.h"

namespace {

// An interrupted run leaves no partial output behind.
void on_interrupt(int signal) {
  exao::remove_unfinished_outputs();
  ::_exit(128 + signal);
}

}  // namespace

int main(int argc, char** argv) {
  std::signal(SIGINT, on_interrupt);
  std::signal(SIGTERM, on_interrupt);

  CLI::App app{"exao: exact ray-cast ambient occlusion (Laine & Karras 2010)"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "exao 0.1.0");
  const std::vector<exao::cli::Command> commands = exao::cli::register_commands(app);
  CLI11_PARSE(app, argc, argv);
  exao::cli::Invocation invocation;
  invocation.args.assign(argv + 1, argv + argc);  // recorded in the parts of sharded jobs
  for (const auto& command : commands) {
    if (const int status = command(invocation); status >= 0) return status;
  }
  return 1;
}

namespace exao::cli {

std::vector<Command> register_commands(CLI::App& app) {
  return {add_render_command(app), add_info_command(app),  add_bench_command(app), add_query_command(app),
          add_bake_command(app),   add_compare_command(app), add_merge_command(app)};
}

}  // namespace exao::cli
