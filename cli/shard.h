#pragma once
// Jobs spread over processes or machines: `--shard K/N` on bake, render, query and bench, the
// partial results ("parts") a shard writes, `--resume DIR` (a bake's chunks kept on disk), and
// what `exao merge` hands back to a command so that it writes the outputs one run would.
//
// A part holds the blocked-ray counts of its receivers (whole chunks of the engine's Morton
// order, engine::Shard) and says what it is of: the command and its words, the folder it ran
// in, the input files (size and hash), K and N, how many receivers the whole job has and a
// digest of them. Merge re-runs the recorded command with every count supplied instead of cast
// (engine::RunOptions::supplied_blocked), so everything after the rays (the atlas, dilation,
// the glTF, EXR, PNG or text) is made once, from the complete answers, by the same code as an
// unsharded run: byte for byte the same files.
//
// File layout (little-endian): the line "EXAOPART 1", a line of JSON (the header), then
// u64 count, count x u32 receiver index, count x u32 blocked count, u64 FNV-1a of those bytes,
// and the line "EXAOEND". A part whose size is not exactly that is truncated.

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "core/error.h"
#include "core/receiver_frame.h"
#include "engine/engine.h"

namespace exao::cli {

/// What exao merge gives the command it re-runs: every receiver's count, in the command's own
/// receiver order, and the figures the receivers must match.
struct MergeInput {
  std::vector<std::uint32_t> blocked;
  std::uint64_t receivers_digest = 0;
  std::string output;  // merge's -o, absolute; empty: the output the parts were made for
  std::string parts;   // "N parts of OUT", for messages
};

/// How a command was asked for, beyond its parsed flags.
struct Invocation {
  std::vector<std::string> args;     // the words after the program name, as given
  const MergeInput* merge = nullptr;  // set by exao merge
};

/// --shard, --shard-count (and --resume for bake).
struct ShardCliOptions {
  std::string shard;                // "K/N", "auto" or empty
  std::optional<std::size_t> count;  // --shard-count: N for Kubernetes' JOB_COMPLETION_INDEX
  std::string resume;               // bake --resume DIR
};

void add_shard_options(CLI::App& app, ShardCliOptions& options, bool resume);

/// The shard asked for, or nullopt without --shard. "auto" takes K and N from a SLURM job array
/// (SLURM_ARRAY_TASK_ID counted from SLURM_ARRAY_TASK_MIN in steps of SLURM_ARRAY_TASK_STEP,
/// SLURM_ARRAY_TASK_COUNT) or a Kubernetes Indexed Job (JOB_COMPLETION_INDEX, with
/// --shard-count N); outside either it fails, saying so. N is at most 65536.
[[nodiscard]] Result<std::optional<engine::Shard>> resolve_shard(const ShardCliOptions& options);

/// FNV-1a digest of every receiver's position, normal and key, in order.
[[nodiscard]] std::uint64_t receivers_digest(std::span<const Receiver> receivers);

/// The part file of `shard` of the job writing `output`: never the output's own name.
[[nodiscard]] std::string part_path(const std::string& output, engine::Shard shard);

/// What a job's parts must agree on.
struct JobRecord {
  std::string command;                // "bake", "render", "query"
  std::vector<std::string> args;      // the command's words without --shard, --shard-count, --resume
  std::string cwd;                    // where relative paths in args are read from
  std::vector<std::string> inputs;    // input files (absolute), hashed
  std::string output;                 // the final output, as the command resolved it
  std::uint64_t receivers = 0;        // of the whole job
  std::uint64_t receivers_digest = 0;
  int samples = 0;
};

/// A command's job record from its invocation (inputs: the files it reads; built-in scene names
/// that are not files are skipped).
[[nodiscard]] JobRecord make_record(const std::string& command, const Invocation& invocation,
                                    const std::vector<std::string>& inputs, const std::string& output,
                                    std::span<const Receiver> receivers, int samples);

/// The sharded run of a command: computes the shard's receivers with `engine` (a progress bar
/// on a terminal) and writes its part beside the output. Returns the exit status.
[[nodiscard]] int run_shard(const JobRecord& record, const engine::Engine& engine, std::span<const Receiver> receivers,
                            engine::Shard shard);

/// Merge mode: fails (naming the parts) unless `receivers` are the ones the parts were made for.
[[nodiscard]] Result<void> check_merge_receivers(const MergeInput& merge, std::span<const Receiver> receivers);

/// bake --resume DIR: every chunk of the job as a part in DIR (those already there, checked
/// against `record`, are kept; the others computed and written one by one, so a killed run loses
/// at most the chunk under way). Returns every receiver's count; prints how many were resumed.
[[nodiscard]] Result<std::vector<std::uint32_t>> run_resumable(const std::string& dir, const JobRecord& record,
                                                               const engine::Engine& engine,
                                                               std::span<const Receiver> receivers);

/// The function of `exao merge`: registered with the other commands.
[[nodiscard]] std::function<int(const Invocation&)> add_merge_command(CLI::App& app);

}  // namespace exao::cli
