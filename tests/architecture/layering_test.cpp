// The architecture's rules, checked on the source tree itself (docs/architecture.md): dependencies point down only,
// the session's wire and engine layers need no sockets, nothing includes in a loop, the product holds no
// instrument. A failure names the file and the include that broke the rule.
#include "include_graph.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <string_view>
#include <vector>

namespace sc::architecture {
namespace {

const IncludeGraph& sourceGraph() {
  static const IncludeGraph graph = readIncludeGraph(SHAPECAST_SOURCE_DIR, {"src"});
  return graph;
}

bool startsWith(std::string_view text, std::string_view prefix) { return text.substr(0, prefix.size()) == prefix; }

/// The project includes a folder's files may write ("spectral/", "session/wire/", …).
struct Layer {
  std::string folder;
  std::vector<std::string> mayInclude;
  bool qt = true;       ///< may include Qt at all
  bool network = true;  ///< may include Qt Network
};

const std::vector<Layer>& layers() {
  static const std::vector<Layer> all{
      {"src/spectral/", {"spectral/"}, false, false},
      {"src/model/", {"spectral/", "model/"}, true, false},
      {"src/session/wire/", {"spectral/", "session/wire/"}, true, false},
      {"src/session/engine/", {"spectral/", "session/wire/", "session/engine/"}, true, false},
      {"src/session/net/", {"spectral/", "session/"}, true, true},
      {"src/app/", {"spectral/", "model/", "session/", "app/", "ui_"}, true, true},
  };
  return all;
}

TEST(Architecture, EveryFolderIncludesOnlyTheLayersBelowIt) {
  int checked = 0;
  for (const auto& entry : sourceGraph().includes) {
    const std::string& file = entry.first;  // not a structured binding: Clang 14 cannot capture one in a lambda
    const std::vector<std::string>& written = entry.second;
    const auto layer =
        std::find_if(layers().begin(), layers().end(), [&file](const Layer& l) { return startsWith(file, l.folder); });
    ASSERT_NE(layer, layers().end()) << file << " is in no known layer: add its folder to layers()";
    for (const std::string& target : written) {
      const bool allowed = std::any_of(layer->mayInclude.begin(), layer->mayInclude.end(),
                                       [&target](const std::string& p) { return startsWith(target, p); });
      EXPECT_TRUE(allowed) << file << " includes \"" << target << "\"";
      ++checked;
    }
    for (const std::string& target : sourceGraph().systemIncludes.at(file)) {
      if (!layer->qt) {
        EXPECT_FALSE(startsWith(target, "Q")) << file << " includes <" << target << "> (no Qt here)";
      }
      if (!layer->network) {
        EXPECT_FALSE(startsWith(target, "QtNetwork") || startsWith(target, "QUdp") || startsWith(target, "QTcp") ||
                     startsWith(target, "QSsl"))
            << file << " includes <" << target << "> (no sockets here)";
      }
    }
  }
  EXPECT_GT(checked, 100) << "the source tree was not found at " << SHAPECAST_SOURCE_DIR;
}

TEST(Architecture, NoTwoSourceFilesIncludeEachOtherEvenThroughOthers) {
  for (const std::vector<std::string>& cycle : unitCycles(sourceGraph())) {
    std::string names;
    for (const std::string& unit : cycle) names += unit + " ";
    ADD_FAILURE() << "include loop: " << names;
  }
}

TEST(Architecture, TheProductHoldsNoExperimentOrScreenshotAutomation) {
  for (const auto& [file, written] : sourceGraph().includes) {
    if (!startsWith(file, "src/app/")) continue;
    for (const std::string_view instrument : {"experiment", "screenshot", "table1", "report/"}) {
      EXPECT_EQ(file.find(instrument), std::string::npos) << file << " looks like an instrument: experiments/";
    }
  }
}

TEST(Architecture, TheCycleFinderFindsALoop) {
  IncludeGraph graph;
  graph.unitEdges["src/a"] = {"src/b"};
  graph.unitEdges["src/b"] = {"src/c"};
  graph.unitEdges["src/c"] = {"src/a"};
  graph.unitEdges["src/d"] = {"src/a"};
  const auto cycles = unitCycles(graph);
  ASSERT_EQ(cycles.size(), 1u);
  EXPECT_EQ(cycles[0].size(), 3u);
}

}  // namespace
}  // namespace sc::architecture
