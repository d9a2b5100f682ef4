#include "include_graph.h"

#include <algorithm>
#include <fstream>
#include <functional>
#include <regex>

namespace sc::architecture {

namespace fs = std::filesystem;

std::string unitOf(const std::string& file) {
  const std::size_t dot = file.find_last_of('.');
  return dot == std::string::npos ? file : file.substr(0, dot);
}

IncludeGraph readIncludeGraph(const fs::path& root, const std::vector<std::string>& folders) {
  static const std::regex include(R"(^\s*#\s*include\s+\"([^\"]+)\")");
  static const std::regex systemInclude(R"(^\s*#\s*include\s+<([^>]+)>)");
  IncludeGraph graph;
  for (const std::string& folder : folders) {
    for (const fs::directory_entry& entry : fs::recursive_directory_iterator(root / folder)) {
      const std::string extension = entry.path().extension().string();
      if (!entry.is_regular_file() || (extension != ".h" && extension != ".cpp")) continue;
      const std::string file = fs::relative(entry.path(), root).generic_string();
      std::vector<std::string>& written = graph.includes[file];
      std::vector<std::string>& system = graph.systemIncludes[file];
      std::ifstream in(entry.path());
      std::smatch match;
      for (std::string line; std::getline(in, line);) {
        if (std::regex_search(line, match, include)) written.push_back(match[1].str());
        if (std::regex_search(line, match, systemInclude)) system.push_back(match[1].str());
      }
    }
  }
  for (const auto& [file, written] : graph.includes) {
    std::set<std::string>& edges = graph.unitEdges[unitOf(file)];
    for (const std::string& target : written) {
      const std::string resolved = "src/" + target;
      if (!graph.includes.contains(resolved)) continue;  // a system or generated header, or another root
      if (unitOf(resolved) != unitOf(file)) edges.insert(unitOf(resolved));
    }
  }
  return graph;
}

std::vector<std::vector<std::string>> unitCycles(const IncludeGraph& graph) {
  // Tarjan's strongly connected components.
  std::map<std::string, int> index, low;
  std::vector<std::string> stack;
  std::set<std::string> onStack;
  std::vector<std::vector<std::string>> cycles;
  int next = 0;
  const std::function<void(const std::string&)> visit = [&](const std::string& unit) {
    index[unit] = low[unit] = next++;
    stack.push_back(unit);
    onStack.insert(unit);
    const auto edges = graph.unitEdges.find(unit);
    if (edges != graph.unitEdges.end()) {
      for (const std::string& target : edges->second) {
        if (!index.contains(target)) {
          visit(target);
          low[unit] = std::min(low[unit], low[target]);
        } else if (onStack.contains(target)) {
          low[unit] = std::min(low[unit], index[target]);
        }
      }
    }
    if (low[unit] != index[unit]) return;
    std::vector<std::string> component;
    std::string member;
    do {
      member = stack.back();
      stack.pop_back();
      onStack.erase(member);
      component.push_back(member);
    } while (member != unit);
    if (component.size() > 1) cycles.push_back(std::move(component));
  };
  for (const auto& [unit, edges] : graph.unitEdges) {
    if (!index.contains(unit)) visit(unit);
  }
  return cycles;
}

}  // namespace sc::architecture
