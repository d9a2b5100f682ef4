#pragma once
// Shared by the fuzz targets of this folder (docs/fuzzing.md): the libFuzzer entry point's declaration, an
// invariant check that aborts (so libFuzzer, and the replay tests, report it as a crash), the fixed keys the
// harnesses authenticate with, and a scratch file for decoders that take a path.

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <span>
#include <string_view>

/// libFuzzer's entry point, defined once per fuzz target. Returns 0 (libFuzzer reserves other values).
extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);

namespace sc::fuzz {

/// Prints `what` to stderr and aborts when `condition` is false: a broken decoder contract is a finding.
void check(bool condition, std::string_view what);

/// The harness input split into its first byte (selects what the harness does with the rest) and the rest.
struct Input {
  std::uint8_t mode = 0;
  std::span<const std::uint8_t> rest;
};
/// Splits `data`; an empty input gives mode 0 and an empty rest.
Input splitMode(const std::uint8_t* data, std::size_t size);

/// Fixed 32-byte datagram key of the harnesses (bytes 1..32) and the peer id it belongs to.
std::span<const std::uint8_t> fixedKey();
inline constexpr std::uint16_t kFixedPeer = 7;

/// One file in a private scratch folder (created on first use under the system temp folder, removed at exit),
/// rewritten by every write(). For decoders whose API takes a path. Not thread-safe.
class ScratchFile {
 public:
  /// `name`: file name inside the scratch folder, e.g. "input.ply" (the extension selects a mesh reader).
  explicit ScratchFile(std::string_view name);
  /// Replaces the file's content with `bytes` and returns its path. Aborts when the file cannot be written.
  const std::filesystem::path& write(std::span<const std::uint8_t> bytes);

 private:
  std::filesystem::path m_path;
};

}  // namespace sc::fuzz
