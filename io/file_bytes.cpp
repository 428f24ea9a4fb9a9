#include "io/file_bytes.h"

#include <algorithm>
#include <filesystem>
#include <fstream>

namespace exao {
namespace {

template <class Bytes>
bool read_into(const std::string& path, Bytes& out, const ProgressCallback& progress) {
  out.clear();
  std::ifstream in(path, std::ios::binary);
  if (!in) return false;
  std::error_code error;
  const auto size = std::filesystem::file_size(path, error);
  if (error) return false;
  out.resize(static_cast<std::size_t>(size));
  constexpr std::size_t kChunk = std::size_t{1} << 24;
  for (std::size_t done = 0; done < out.size();) {
    const std::size_t chunk = std::min(kChunk, out.size() - done);
    in.read(reinterpret_cast<char*>(out.data()) + done, static_cast<std::streamsize>(chunk));
    if (static_cast<std::size_t>(in.gcount()) != chunk) return false;
    done += chunk;
    if (progress) progress(done, out.size());
  }
  return true;
}

}  // namespace

bool read_file_bytes(const std::string& path, std::string& out, const ProgressCallback& progress) {
  return read_into(path, out, progress);
}

bool read_file_bytes(const std::string& path, std::vector<unsigned char>& out, const ProgressCallback& progress) {
  return read_into(path, out, progress);
}

}  // namespace exao
