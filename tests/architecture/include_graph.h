#pragma once
// The project's include graph, read from the source tree as text (docs/architecture.md, "What may include what"):
// every `#include "…"` of every .h/.cpp under a root, resolved against that root. A *unit* is a header and its
// .cpp (the path without extension): the graph the layering tests check for loops is the graph of units, so
// a.cpp → b.h together with b.cpp → a.h counts as a loop.
// Cost: reads every file once, O(total bytes).

#include <filesystem>
#include <map>
#include <set>
#include <string>
#include <vector>

namespace sc::architecture {

struct IncludeGraph {
  /// file (relative to the root, '/'-separated) → the quoted includes it writes, as written.
  std::map<std::string, std::vector<std::string>> includes;
  /// file → the angle-bracket includes it writes (<QtNetwork/QUdpSocket>, <vector>, …), as written.
  std::map<std::string, std::vector<std::string>> systemIncludes;
  /// unit → units it includes (only includes that name a file under the root; self-edges dropped).
  std::map<std::string, std::set<std::string>> unitEdges;
};

/// Reads every .h and .cpp below root/folder for each folder (e.g. "src"), includes resolved against root/src.
[[nodiscard]] IncludeGraph readIncludeGraph(const std::filesystem::path& root, const std::vector<std::string>& folders);

/// The unit of a file path: the path without its extension.
[[nodiscard]] std::string unitOf(const std::string& file);

/// One cycle of units per strongly connected component with more than one unit (empty: no loop).
[[nodiscard]] std::vector<std::vector<std::string>> unitCycles(const IncludeGraph& graph);

}  // namespace sc::architecture
