#include "cli/shard.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>

#include <unistd.h>

#include <nlohmann/json.hpp>

#include "cli/commands.h"
#include "cli/option_flags.h"
#include "cli/progress_bar.h"
#include "core/atomic_write.h"

namespace exao::cli {
namespace fs = std::filesystem;

namespace {

constexpr char kMagic[] = "EXAOPART 1\n";
constexpr char kEnd[] = "EXAOEND\n";
// Parts of more shards than this would each hold less than a chunk of any batch that fits in
// memory; the bound also keeps shard_chunks' products far from overflow.
constexpr std::size_t kMaxShards = 65536;

// FNV-1a, 64 bits: a digest to tell inputs and parts apart, not a defence against forgery.
struct Fnv {
  std::uint64_t h = 1469598103934665603ull;
  void add(const void* data, std::size_t size) {
    const auto* p = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < size; ++i) h = (h ^ p[i]) * 1099511628211ull;
  }
};

std::string hex(std::uint64_t v) {
  char text[17];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(v));
  return text;
}

Result<std::string> hash_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return fail(path + ": cannot be read");
  Fnv fnv;
  std::vector<char> block(1 << 16);
  while (in) {
    in.read(block.data(), static_cast<std::streamsize>(block.size()));
    fnv.add(block.data(), static_cast<std::size_t>(in.gcount()));
  }
  return hex(fnv.h);
}

Result<std::size_t> parse_count(const std::string& text, const std::string& what) {
  if (text.empty() || text.size() > 9 || !std::all_of(text.begin(), text.end(), [](char c) { return c >= '0' && c <= '9'; })) {
    return fail(what + ": '" + text + "' is not a whole number");
  }
  return static_cast<std::size_t>(std::stoull(text));
}

std::optional<std::string> env(const char* name) {
  const char* value = std::getenv(name);
  if (value == nullptr || *value == '\0') return std::nullopt;
  return std::string(value);
}

Result<engine::Shard> checked(std::size_t k, std::size_t n, const std::string& what) {
  if (n < 1 || n > kMaxShards) return fail(what + ": N must be from 1 to " + std::to_string(kMaxShards) + ", got " + std::to_string(n));
  if (k >= n) return fail(what + ": K must be from 0 to N - 1 = " + std::to_string(n - 1) + ", got " + std::to_string(k));
  return engine::Shard{k, n};
}

// The words of a command without the flags that say which part it is: what every part of a job
// must share.
std::vector<std::string> job_args(const std::vector<std::string>& args) {
  std::vector<std::string> out;
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    bool dropped = false;
    for (const char* flag : {"--shard", "--shard-count", "--resume"}) {
      if (a == flag) {
        ++i;  // and its value
        dropped = true;
      } else if (a.rfind(std::string(flag) + "=", 0) == 0) {
        dropped = true;
      }
    }
    if (!dropped) out.push_back(a);
  }
  return out;
}

nlohmann::json to_json(const JobRecord& r) {
  return {{"command", r.command}, {"args", r.args}, {"cwd", r.cwd}, {"inputs", r.inputs}, {"output", r.output},
          {"receivers", r.receivers}, {"receivers_digest", hex(r.receivers_digest)}, {"samples", r.samples}};
}

struct InputHash {
  std::string path;
  std::string hash;
};

struct Part {
  std::string path;
  JobRecord record;
  std::vector<InputHash> hashes;
  engine::Shard shard;
  std::vector<std::uint32_t> index, blocked;
};

Result<void> write_part(const std::string& path, const JobRecord& record, engine::Shard shard,
                        std::span<const std::uint32_t> index, std::span<const std::uint32_t> blocked) {
  nlohmann::json header = to_json(record);
  header["shard"] = shard.index;
  header["shards"] = shard.count;
  nlohmann::json hashes = nlohmann::json::array();
  for (const std::string& input : record.inputs) {
    Result<std::string> hash = hash_file(input);
    if (!hash) return std::unexpected(hash.error());
    hashes.push_back({{"path", input}, {"size", fs::file_size(input)}, {"fnv1a64", *hash}});
  }
  header["input_hashes"] = hashes;
  return write_atomically(path, [&](const std::string& temp) -> Result<void> {
    std::ofstream out(temp, std::ios::binary);
    const std::string text = header.dump() + "\n";
    out.write(kMagic, static_cast<std::streamsize>(std::strlen(kMagic)));
    out.write(text.data(), static_cast<std::streamsize>(text.size()));
    const std::uint64_t count = index.size();
    Fnv fnv;
    fnv.add(&count, sizeof count);
    fnv.add(index.data(), index.size_bytes());
    fnv.add(blocked.data(), blocked.size_bytes());
    out.write(reinterpret_cast<const char*>(&count), sizeof count);
    out.write(reinterpret_cast<const char*>(index.data()), static_cast<std::streamsize>(index.size_bytes()));
    out.write(reinterpret_cast<const char*>(blocked.data()), static_cast<std::streamsize>(blocked.size_bytes()));
    out.write(reinterpret_cast<const char*>(&fnv.h), sizeof fnv.h);
    out.write(kEnd, static_cast<std::streamsize>(std::strlen(kEnd)));
    out.close();
    if (!out) return fail(path + ": cannot be written (" + system_reason() + ")");
    return {};
  });
}

// Reads and checks one part; every error names it.
Result<Part> read_part(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return fail(path + ": cannot be read");
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::size_t magic = std::strlen(kMagic);
  if (bytes.compare(0, magic, kMagic) != 0) return fail(path + ": not an exao part (no 'EXAOPART 1' line)");
  const std::size_t eol = bytes.find('\n', magic);
  if (eol == std::string::npos) return fail(path + ": truncated (the header line is cut off)");
  Part part;
  part.path = path;
  try {
    const nlohmann::json h = nlohmann::json::parse(bytes.substr(magic, eol - magic));
    JobRecord& r = part.record;
    r.command = h.at("command").get<std::string>();
    r.args = h.at("args").get<std::vector<std::string>>();
    r.cwd = h.at("cwd").get<std::string>();
    r.inputs = h.at("inputs").get<std::vector<std::string>>();
    r.output = h.at("output").get<std::string>();
    r.receivers = h.at("receivers").get<std::uint64_t>();
    r.receivers_digest = std::stoull(h.at("receivers_digest").get<std::string>(), nullptr, 16);
    r.samples = h.at("samples").get<int>();
    part.shard = {h.at("shard").get<std::size_t>(), h.at("shards").get<std::size_t>()};
    for (const auto& input : h.at("input_hashes")) {
      part.hashes.push_back({input.at("path").get<std::string>(), input.at("fnv1a64").get<std::string>()});
    }
  } catch (const std::exception& e) {
    return fail(path + ": its header is not an exao part's (" + std::string(e.what()) + ")");
  }
  if (part.shard.count < 1 || part.shard.count > kMaxShards || part.shard.index >= part.shard.count) {
    return fail(path + ": its header names part " + std::to_string(part.shard.index) + " of " + std::to_string(part.shard.count));
  }
  const std::size_t at = eol + 1;
  std::uint64_t count = 0;
  if (bytes.size() < at + sizeof count) return fail(path + ": truncated (no receiver count)");
  std::memcpy(&count, bytes.data() + at, sizeof count);
  // Bounded by the file's size before any arithmetic on it: a hand-made count cannot overflow.
  if (count > bytes.size() / 8) return fail(path + ": truncated (it holds fewer receivers than its count, " + std::to_string(count) + ")");
  if (count > part.record.receivers) {
    return fail(path + ": holds " + std::to_string(count) + " receivers of a job of " + std::to_string(part.record.receivers));
  }
  const std::size_t expected = at + sizeof count + 8 * count + sizeof(std::uint64_t) + std::strlen(kEnd);
  if (bytes.size() != expected) {
    return fail(path + ": " + (bytes.size() < expected ? "truncated" : "has trailing bytes") + " (" +
                std::to_string(bytes.size()) + " bytes, its header and count make " + std::to_string(expected) + ")");
  }
  part.index.resize(count);
  part.blocked.resize(count);
  const char* p = bytes.data() + at + sizeof count;
  if (count > 0) {  // an empty part's vectors have no storage: memcpy must not see their null data
    std::memcpy(part.index.data(), p, 4 * count);
    std::memcpy(part.blocked.data(), p + 4 * count, 4 * count);
  }
  Fnv fnv;
  fnv.add(bytes.data() + at, sizeof count + 8 * count);
  std::uint64_t stored = 0;
  std::memcpy(&stored, p + 8 * count, sizeof stored);
  if (stored != fnv.h || bytes.compare(expected - std::strlen(kEnd), std::string::npos, kEnd) != 0) {
    return fail(path + ": damaged (its checksum does not match its contents)");
  }
  return part;
}

// Why two parts cannot be of one job, or empty.
std::string mismatch(const Part& a, const Part& b) {
  if (a.record.command != b.record.command) return "is a part of exao " + a.record.command + ", not exao " + b.record.command;
  std::vector<std::string> ia, ib;
  for (const InputHash& h : a.hashes) ia.push_back(h.path + "@" + h.hash);
  for (const InputHash& h : b.hashes) ib.push_back(h.path + "@" + h.hash);
  if (ia != ib || a.record.inputs != b.record.inputs) return "was made from other inputs";
  if (a.record.args != b.record.args || a.record.cwd != b.record.cwd || a.record.samples != b.record.samples) {
    std::string args;
    for (const std::string& w : a.record.args) args += (args.empty() ? "" : " ") + w;
    return "was made with other options ('" + args + "')";
  }
  if (a.shard.count != b.shard.count) {
    return "is one of " + std::to_string(a.shard.count) + " parts, not of " + std::to_string(b.shard.count);
  }
  if (a.record.receivers != b.record.receivers || a.record.receivers_digest != b.record.receivers_digest) {
    return "was made for other receivers";
  }
  if (a.record.output != b.record.output) return "is a part of " + a.record.output + ", not " + b.record.output;
  return {};
}

// The parts of one job, checked against each other and against the inputs as they are now;
// every receiver's count in the job's order.
Result<std::vector<std::uint32_t>> combine(const std::vector<Part>& parts) {
  const Part& first = parts.front();
  std::map<std::size_t, const Part*> by_index;
  for (const Part& part : parts) {
    if (const std::string why = mismatch(part, first); !why.empty()) {
      return fail(part.path + ": does not belong with " + first.path + ": it " + why);
    }
    auto [it, added] = by_index.try_emplace(part.shard.index, &part);
    if (!added) {
      return fail(part.path + ": a second part " + std::to_string(part.shard.index) + " of " +
                  std::to_string(part.shard.count) + " (the first is " + it->second->path + ")");
    }
  }
  for (std::size_t k = 0; k < first.shard.count; ++k) {
    if (!by_index.count(k)) {
      return fail(part_path(first.record.output, {k, first.shard.count}) + ": missing (part " + std::to_string(k) + " of " +
                  std::to_string(first.shard.count) + " was not given)");
    }
  }
  for (const InputHash& h : first.hashes) {
    Result<std::string> now = hash_file(h.path);
    if (!now) return std::unexpected(now.error());
    if (*now != h.hash) return fail(h.path + ": changed since the parts were made (" + first.path + ")");
  }
  // Counted before the job's array is made: a header cannot ask for more memory than its parts hold.
  std::uint64_t held = 0;
  for (const Part& part : parts) held += part.index.size();
  if (held != first.record.receivers) {
    return fail(first.path + ": the parts hold " + std::to_string(held) + " receivers of the job's " +
                std::to_string(first.record.receivers));
  }
  constexpr std::uint32_t kUnset = ~std::uint32_t{0};
  std::vector<std::uint32_t> blocked(first.record.receivers, kUnset);
  for (const Part& part : parts) {
    for (std::size_t i = 0; i < part.index.size(); ++i) {
      const std::uint32_t r = part.index[i];
      if (r >= blocked.size() || blocked[r] != kUnset || part.blocked[i] > static_cast<std::uint32_t>(first.record.samples)) {
        return fail(part.path + ": damaged (receiver " + std::to_string(r) + " is out of range or given twice)");
      }
      blocked[r] = part.blocked[i];
    }
  }
  // Every part present and none overlapping, yet receivers missing: a part holds fewer than its
  // chunks (only a hand-made file can).
  for (std::size_t r = 0; r < blocked.size(); ++r) {
    if (blocked[r] == kUnset) return fail(first.path + ": the parts do not hold receiver " + std::to_string(r));
  }
  return blocked;
}

}  // namespace

void add_shard_options(CLI::App& app, ShardCliOptions& options, bool resume) {
  app.add_option("--shard", options.shard,
                 "Compute part K of N (K/N, from 0) and write it beside the output for exao merge; auto: K and N from a "
                 "SLURM job array or a Kubernetes Indexed Job (with --shard-count)");
  app.add_option("--shard-count", options.count, "N for --shard auto under Kubernetes (JOB_COMPLETION_INDEX is K)");
  if (resume) {
    app.add_option("--resume", options.resume,
                   "Keep every finished chunk in DIR and reuse the ones there: a killed bake goes on where it stopped");
  }
}

Result<std::optional<engine::Shard>> resolve_shard(const ShardCliOptions& options) {
  if (options.shard.empty()) {
    if (options.count) return fail("--shard-count: only with --shard auto");
    return std::optional<engine::Shard>{};
  }
  if (!options.resume.empty()) return fail("--resume: not with --shard (a shard is a part already; resume the whole job)");
  if (options.shard != "auto") {
    if (options.count) return fail("--shard-count: only with --shard auto");
    const std::size_t slash = options.shard.find('/');
    if (slash == std::string::npos) return fail("--shard: must be K/N or auto, got '" + options.shard + "'");
    Result<std::size_t> k = parse_count(options.shard.substr(0, slash), "--shard");
    if (!k) return std::unexpected(k.error());
    Result<std::size_t> n = parse_count(options.shard.substr(slash + 1), "--shard");
    if (!n) return std::unexpected(n.error());
    Result<engine::Shard> shard = checked(*k, *n, "--shard " + options.shard);
    if (!shard) return std::unexpected(shard.error());
    return std::optional<engine::Shard>{*shard};
  }
  if (const auto id = env("SLURM_ARRAY_TASK_ID")) {
    // A SLURM array's tasks are MIN, MIN + STEP, ... (--array=0-6:2 gives 0 2 4 6).
    const auto min = env("SLURM_ARRAY_TASK_MIN");
    const auto count = env("SLURM_ARRAY_TASK_COUNT");
    if (!min || !count) return fail("--shard auto: SLURM_ARRAY_TASK_ID is set but not SLURM_ARRAY_TASK_MIN and SLURM_ARRAY_TASK_COUNT");
    Result<std::size_t> i = parse_count(*id, "SLURM_ARRAY_TASK_ID");
    Result<std::size_t> lo = parse_count(*min, "SLURM_ARRAY_TASK_MIN");
    Result<std::size_t> n = parse_count(*count, "SLURM_ARRAY_TASK_COUNT");
    Result<std::size_t> step = parse_count(env("SLURM_ARRAY_TASK_STEP").value_or("1"), "SLURM_ARRAY_TASK_STEP");
    for (const auto* r : {&i, &lo, &n, &step}) {
      if (!*r) return std::unexpected(r->error());
    }
    if (*i < *lo || *step == 0 || (*i - *lo) % *step != 0) {
      return fail("--shard auto: SLURM_ARRAY_TASK_ID " + *id + " is not MIN " + *min + " plus a multiple of the step");
    }
    if (options.count && *options.count != *n) {
      return fail("--shard-count " + std::to_string(*options.count) + ": the SLURM array has " + *count + " tasks");
    }
    Result<engine::Shard> shard = checked((*i - *lo) / *step, *n, "--shard auto (SLURM array)");
    if (!shard) return std::unexpected(shard.error());
    return std::optional<engine::Shard>{*shard};
  }
  if (const auto index = env("JOB_COMPLETION_INDEX")) {
    if (!options.count) return fail("--shard auto: JOB_COMPLETION_INDEX is set (a Kubernetes Indexed Job): give its completions as --shard-count N");
    Result<std::size_t> k = parse_count(*index, "JOB_COMPLETION_INDEX");
    if (!k) return std::unexpected(k.error());
    Result<engine::Shard> shard = checked(*k, *options.count, "--shard auto (JOB_COMPLETION_INDEX)");
    if (!shard) return std::unexpected(shard.error());
    return std::optional<engine::Shard>{*shard};
  }
  return fail("--shard auto: neither SLURM_ARRAY_TASK_ID (a SLURM job array) nor JOB_COMPLETION_INDEX (a Kubernetes "
              "Indexed Job) is set; give --shard K/N");
}

std::uint64_t receivers_digest(std::span<const Receiver> receivers) {
  Fnv fnv;
  for (const Receiver& r : receivers) {
    fnv.add(&r.position, sizeof r.position);
    fnv.add(&r.normal, sizeof r.normal);
    fnv.add(&r.key, sizeof r.key);
  }
  return fnv.h;
}

std::string part_path(const std::string& output, engine::Shard shard) {
  char suffix[64];
  std::snprintf(suffix, sizeof suffix, ".part-%04zu-of-%04zu.exao", shard.index, shard.count);
  return output + suffix;
}

JobRecord make_record(const std::string& command, const Invocation& invocation, const std::vector<std::string>& inputs,
                      const std::string& output, std::span<const Receiver> receivers, int samples) {
  JobRecord r;
  r.command = command;
  r.args = job_args(invocation.args);
  std::error_code ec;
  r.cwd = fs::current_path(ec).string();
  for (const std::string& input : inputs) {
    if (!input.empty() && fs::is_regular_file(input, ec)) r.inputs.push_back(fs::absolute(input, ec).lexically_normal().string());
  }
  r.output = output;
  r.receivers = receivers.size();
  r.receivers_digest = receivers_digest(receivers);
  r.samples = samples;
  return r;
}

namespace {

// The counts of `shard`'s receivers, in the engine's order.
Result<std::pair<std::vector<std::uint32_t>, std::vector<std::uint32_t>>> compute_shard(
    const engine::Engine& engine, std::span<const Receiver> receivers, engine::Shard shard, const std::string& label) {
  std::vector<std::uint32_t> index = engine::shard_receivers(receivers, shard);
  std::vector<std::uint32_t> all(receivers.size(), 0);
  {
    ProgressBar bar(label);
    engine::RunOptions run;
    run.progress = bar.callback();
    run.shard = shard;
    engine::Outputs outputs;
    outputs.blocked = all;
    if (auto ok = engine.run(receivers, outputs, run); !ok) return std::unexpected(ok.error());
  }
  std::vector<std::uint32_t> blocked(index.size());
  for (std::size_t i = 0; i < index.size(); ++i) blocked[i] = all[index[i]];
  return std::pair{std::move(index), std::move(blocked)};
}

}  // namespace

int run_shard(const JobRecord& record, const engine::Engine& engine, std::span<const Receiver> receivers,
              engine::Shard shard) {
  const std::string path = part_path(record.output, shard);
  auto computed = compute_shard(engine, receivers, shard,
                                "shard " + std::to_string(shard.index) + "/" + std::to_string(shard.count));
  if (!computed) return report(computed.error());
  if (auto ok = write_part(path, record, shard, computed->first, computed->second); !ok) return report(ok.error());
  const auto [first, last] = engine::shard_chunks(receivers.size(), shard);
  std::printf("shard %zu/%zu: %zu of %zu receivers (chunks %zu to %zu of %zu) -> %s\n", shard.index, shard.count,
              computed->first.size(), receivers.size(), first, last, (receivers.size() + engine::kChunk - 1) / engine::kChunk,
              path.c_str());
  return 0;
}

Result<void> check_merge_receivers(const MergeInput& merge, std::span<const Receiver> receivers) {
  if (receivers.size() != merge.blocked.size() || receivers_digest(receivers) != merge.receivers_digest) {
    return fail(merge.parts + ": made for other receivers (" + std::to_string(merge.blocked.size()) +
                ") than the input gives now (" + std::to_string(receivers.size()) + ")");
  }
  return {};
}

Result<std::vector<std::uint32_t>> run_resumable(const std::string& dir, const JobRecord& record,
                                                 const engine::Engine& engine, std::span<const Receiver> receivers) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (!fs::is_directory(dir, ec)) return fail(dir + ": cannot be made a folder for --resume");
  const std::size_t chunks = std::max<std::size_t>(1, (receivers.size() + engine::kChunk - 1) / engine::kChunk);
  // Parts of another job in DIR are refused, not replaced: the folder may be another bake's.
  std::vector<Part> found;
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    const std::string name = entry.path().filename().string();
    if (name.size() < 5 || name.compare(name.size() - 5, 5, ".exao") != 0 || name[0] == '.') continue;
    Result<Part> part = read_part(entry.path().string());
    if (!part) return std::unexpected(part.error());
    Part mine;
    mine.record = record;
    mine.shard = {0, chunks};
    for (const std::string& input : record.inputs) {
      Result<std::string> hash = hash_file(input);
      if (!hash) return std::unexpected(hash.error());
      mine.hashes.push_back({input, *hash});
    }
    // The output name is not the job: a resumed bake may write elsewhere.
    part->record.output = record.output;
    if (const std::string why = mismatch(*part, mine); !why.empty()) {
      return fail(part->path + ": not a part of this bake (it " + why + "): --resume needs a folder of its own parts");
    }
    found.push_back(std::move(*part));
  }
  std::vector<std::uint32_t> blocked(receivers.size(), 0);
  std::vector<bool> have(chunks, false);
  for (const Part& part : found) {
    have[part.shard.index] = true;
    for (std::size_t i = 0; i < part.index.size(); ++i) {
      if (part.index[i] >= blocked.size()) return fail(part.path + ": damaged (receiver out of range)");
      blocked[part.index[i]] = part.blocked[i];
    }
  }
  const std::size_t resumed = static_cast<std::size_t>(std::count(have.begin(), have.end(), true));
  if (resumed > 0) std::printf("resumed %zu of %zu chunks from %s\n", resumed, chunks, dir.c_str());
  for (std::size_t c = 0; c < chunks; ++c) {
    if (have[c]) continue;
    const engine::Shard shard{c, chunks};
    auto computed = compute_shard(engine, receivers, shard, "chunk " + std::to_string(c + 1) + "/" + std::to_string(chunks));
    if (!computed) return std::unexpected(computed.error());
    const std::string path = (fs::path(dir) / fs::path(part_path("chunk", shard)).filename()).string();
    if (auto ok = write_part(path, record, shard, computed->first, computed->second); !ok) return std::unexpected(ok.error());
    for (std::size_t i = 0; i < computed->first.size(); ++i) blocked[computed->first[i]] = computed->second[i];
  }
  return blocked;
}

namespace {

struct MergeOptions {
  std::vector<std::string> parts;
  std::string output;
};

int run_merge(const MergeOptions& options) {
  // Every part is read and checked, and the inputs hashed, before the command runs: nothing is
  // written unless all of them are good.
  std::vector<Part> parts;
  for (const std::string& path : options.parts) {
    Result<Part> part = read_part(path);
    if (!part) return report(part.error());
    parts.push_back(std::move(*part));
  }
  Result<std::vector<std::uint32_t>> blocked = combine(parts);
  if (!blocked) return report(blocked.error());
  const JobRecord& record = parts.front().record;
  MergeInput merge;
  merge.blocked = std::move(*blocked);
  merge.receivers_digest = record.receivers_digest;
  merge.parts = parts.front().path + " and the other " + std::to_string(parts.size() - 1) + " part(s)";
  std::error_code ec;
  if (!options.output.empty()) merge.output = fs::absolute(options.output, ec).lexically_normal().string();
  // The recorded command runs where it was recorded, so that its relative paths mean what they
  // meant; merge's own -o was made absolute above.
  if (::chdir(record.cwd.c_str()) != 0) return report(Error{record.cwd + ": the folder the parts were made in cannot be entered"});
  CLI::App app;
  app.require_subcommand(1);
  const std::vector<Command> commands = register_commands(app);
  std::vector<std::string> words = record.args;
  std::reverse(words.begin(), words.end());  // CLI11 takes the words last first
  try {
    app.parse(words);
  } catch (const CLI::ParseError& e) {
    return report(Error{parts.front().path + ": its recorded command no longer parses (" + std::string(e.what()) + ")"});
  }
  Invocation invocation;
  invocation.args = record.args;
  invocation.merge = &merge;
  for (const Command& command : commands) {
    if (const int status = command(invocation); status >= 0) return status;
  }
  return 1;
}

}  // namespace

std::function<int(const Invocation&)> add_merge_command(CLI::App& app) {
  auto options = std::make_shared<MergeOptions>();
  CLI::App* command = app.add_subcommand(
      "merge", "Put the parts of a sharded bake, render or query together: byte for byte the output of one run");
  command->add_option("parts", options->parts, "Every part of the job (PART.exao ...)")->required();
  command->add_option("-o,--output", options->output, "The output (default: the one the parts were made for)");
  return [options, command](const Invocation&) { return command->parsed() ? run_merge(*options) : -1; };
}

}  // namespace exao::cli
