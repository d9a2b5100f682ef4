#include "app/cli/peak_memory.h"

#include <sys/resource.h>

namespace sc::app {

double peakResidentMegabytes() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_maxrss) / 1024.0;  // Linux reports KiB
}

}  // namespace sc::app
