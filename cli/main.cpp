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
  const std::vector<exao::cli::Command> commands = {
      exao::cli::add_render_command(app),
      exao::cli::add_info_command(app),
      exao::cli::add_bench_command(app),
      exao::cli::add_query_command(app),
      exao::cli::add_bake_command(app),
      exao::cli::add_compare_command(app),
  };
  CLI11_PARSE(app, argc, argv);
  for (const auto& command : commands) {
    if (const int status = command(); status >= 0) return status;
  }
  return 1;
}
