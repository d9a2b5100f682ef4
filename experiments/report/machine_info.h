#pragma once
// A one-line description of the machine a benchmark ran on.

#include <QString>

namespace sc::report {

/// "CPU model, N logical cores, X GiB RAM, kernel K" read from /proc and uname. Cost: a few small file reads.
QString machineDescription();

}  // namespace sc::report
