// adviseHugePages(): a buffer advised before its first write is backed by transparent huge pages where the kernel
// allows them (THP "always" or "madvise"), as /proc/self/smaps reports.

#include "spectral/huge_pages.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>

namespace sc::spectral::detail {
namespace {

/// The kernel's THP mode: the bracketed word of /sys/kernel/mm/transparent_hugepage/enabled, or "" when absent.
std::string transparentHugePageMode() {
  std::ifstream file("/sys/kernel/mm/transparent_hugepage/enabled");
  std::string line;
  std::getline(file, line);
  const auto open = line.find('['), close = line.find(']');
  return open == std::string::npos || close == std::string::npos ? "" : line.substr(open + 1, close - open - 1);
}

/// AnonHugePages (KiB) of the mapping of /proc/self/smaps that contains `address`, or -1 when none does.
long anonHugePagesKiB(const void* address) {
  std::ifstream smaps("/proc/self/smaps");
  const auto at = reinterpret_cast<std::uintptr_t>(address);
  std::string line;
  bool inside = false;
  while (std::getline(smaps, line)) {
    std::uintptr_t begin = 0, end = 0;
    char dash = 0;
    std::istringstream range(line);
    if (range >> std::hex >> begin >> dash >> end && dash == '-') {
      inside = begin <= at && at < end;
    } else if (inside && line.rfind("AnonHugePages:", 0) == 0) {
      return std::stol(line.substr(14));
    }
  }
  return -1;
}

TEST(HugePages, AnAdvisedBufferIsBackedByHugePagesWhereTheKernelAllowsThem) {
  const std::string mode = transparentHugePageMode();
  if (mode != "madvise" && mode != "always") GTEST_SKIP() << "transparent huge pages are off here (" << mode << ")";
  constexpr std::size_t kBytes = std::size_t{64} << 20;
  const auto buffer = std::make_unique_for_overwrite<char[]>(kBytes);
  adviseHugePages(buffer.get(), kBytes);
  std::memset(buffer.get(), 1, kBytes);  // the first writes
  const long huge = anonHugePagesKiB(buffer.get() + kBytes / 2);
  ASSERT_GE(huge, 0) << "no mapping holds the buffer";
  // The kernel may fall back to small pages when it finds no free 2 MiB block; on an idle test machine it does not.
  EXPECT_GE(huge, 32 * 1024) << "at least half of the 64 MiB buffer on huge pages (mode " << mode << ")";
}

}  // namespace
}  // namespace sc::spectral::detail
