// exao: exact ray-cast ambient occlusion. See README.md for every subcommand.

#include <csignal>
#include <string>
#include <vector>

#include <unistd.h>

#include "cli/program.h"
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
  const std::vector<std::string> args(argv + 1, argv + argc);
  return exao::cli::run_program(args);
}
