#pragma once
// Process memory figures for the CLI's reports.

namespace sc::app {

/// Peak resident set size of this process so far, in MiB (getrusage ru_maxrss). Cost: one system call.
double peakResidentMegabytes();

}  // namespace sc::app
