#include "fuzz_support.h"

#include <array>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <numeric>
#include <string>
#include <system_error>

#include <unistd.h>

namespace sc::fuzz {

namespace {

/// The scratch folder of this process, removed with its content at exit.
class ScratchFolder {
 public:
  ScratchFolder() : m_path(std::filesystem::temp_directory_path() / ("shapecast-fuzz-" + std::to_string(::getpid()))) {
    std::filesystem::create_directories(m_path);
  }
  ~ScratchFolder() {
    std::error_code ignored;
    std::filesystem::remove_all(m_path, ignored);
  }
  ScratchFolder(const ScratchFolder&) = delete;
  ScratchFolder& operator=(const ScratchFolder&) = delete;
  const std::filesystem::path& path() const { return m_path; }

 private:
  std::filesystem::path m_path;
};

const std::filesystem::path& scratchFolder() {
  static const ScratchFolder folder;
  return folder.path();
}

}  // namespace

void check(bool condition, std::string_view what) {
  if (condition) return;
  std::fprintf(stderr, "fuzz invariant broken: %.*s\n", static_cast<int>(what.size()), what.data());
  std::abort();
}

Input splitMode(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return {};
  return {data[0], std::span(data + 1, size - 1)};
}

std::span<const std::uint8_t> fixedKey() {
  static const std::array<std::uint8_t, 32> key = [] {
    std::array<std::uint8_t, 32> bytes{};
    std::iota(bytes.begin(), bytes.end(), std::uint8_t{1});
    return bytes;
  }();
  return key;
}

ScratchFile::ScratchFile(std::string_view name) : m_path(scratchFolder() / name) {}

const std::filesystem::path& ScratchFile::write(std::span<const std::uint8_t> bytes) {
  std::ofstream out(m_path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  out.close();
  check(static_cast<bool>(out), "scratch file written");
  return m_path;
}

}  // namespace sc::fuzz
