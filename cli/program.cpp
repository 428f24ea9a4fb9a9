#include "cli/program.h"

#include <algorithm>

#include <CLI/CLI.hpp>

#include "cli/commands.h"
#include "core/atomic_write.h"

namespace exao::cli {
namespace {

const Embedding* g_embedding = nullptr;

// Restores the previous embedding however run_program leaves (a cancelling exception included).
struct EmbeddingScope {
  const Embedding* saved;
  explicit EmbeddingScope(const Embedding* e) : saved(g_embedding) { g_embedding = e; }
  ~EmbeddingScope() { g_embedding = saved; }
  EmbeddingScope(const EmbeddingScope&) = delete;
  EmbeddingScope& operator=(const EmbeddingScope&) = delete;
};

}  // namespace

const Embedding* embedding() { return g_embedding; }

std::vector<Command> register_commands(CLI::App& app) {
  return {add_render_command(app), add_info_command(app),    add_bench_command(app), add_query_command(app),
          add_bake_command(app),   add_compare_command(app), add_merge_command(app)};
}

int run_program(const std::vector<std::string>& args, const Embedding* embedding) {
  const EmbeddingScope scope(embedding);
  CLI::App app{"exao: exact ray-cast ambient occlusion (Laine & Karras 2010)"};
  app.name("exao");
  app.require_subcommand(1);
  app.set_version_flag("--version", "exao 0.1.0");
  const std::vector<Command> commands = register_commands(app);
  try {
    // CLI11 takes a vector of arguments last first.
    std::vector<std::string> reversed(args.rbegin(), args.rend());
    app.parse(reversed);
  } catch (const CLI::ParseError& e) {
    if (embedding && embedding->error && e.get_exit_code() != 0) {
      embedding->error(e.what());
      return e.get_exit_code();
    }
    return app.exit(e);
  }
  try {
    Invocation invocation;
    invocation.args = args;  // recorded in the parts of sharded jobs
    for (const Command& command : commands) {
      if (const int status = command(invocation); status >= 0) return status;
    }
  } catch (...) {
    // A cancelled (or failed) embedded run leaves no partial output behind, as an interrupted
    // program does (main.cpp's signal handler).
    remove_unfinished_outputs();
    throw;
  }
  return 1;
}

}  // namespace exao::cli
