#include "spectral/level_vertex_map.h"

#include "spectral/hausdorff.h"

#include <algorithm>
#include <cstddef>
#include <optional>
#include <vector>

namespace sc::spectral {

LocatedFullVertices locateFullVertices(const ResolutionLevel& level, std::span<const DisplayVertexId> displayed) {
  struct Found {
    FullVertexId id;
    Eigen::Index row;  // the displayed vertex
  };
  std::vector<Found> found;
  found.reserve(displayed.size());
  for (const DisplayVertexId d : displayed) {
    if (const std::optional<FullVertexId> id = dominantFullVertex(level.P, d);
        id && static_cast<Eigen::Index>(d.index()) < level.restV.rows()) {
      found.push_back({*id, static_cast<Eigen::Index>(d.index())});
    }
  }
  std::stable_sort(found.begin(), found.end(), [](const Found& a, const Found& b) { return a.id < b.id; });
  found.erase(std::unique(found.begin(), found.end(), [](const Found& a, const Found& b) { return a.id == b.id; }),
              found.end());
  LocatedFullVertices located;
  located.ids.reserve(found.size());
  located.points.resize(static_cast<Eigen::Index>(found.size()), 3);
  for (std::size_t k = 0; k < found.size(); ++k) {
    located.ids.push_back(found[k].id);
    located.points.row(static_cast<Eigen::Index>(k)) = level.restV.row(found[k].row);
  }
  return located;
}

DisplayVertexIds displayedVertices(const ResolutionLevel& level, const LocatedFullVertices& full) {
  const FullVertexIds& ids = full.ids;
  if (ids.empty()) return {};
  std::vector<char> shown(ids.size(), 0);
  DisplayVertexIds out;
  // === every displayed vertex that stands for one of the ids (ascending by construction)
  for (Eigen::Index i = 0; i < level.P.rows(); ++i) {
    const std::optional<FullVertexId> id = dominantFullVertex(level.P, DisplayVertexId(static_cast<std::uint32_t>(i)));
    if (!id) continue;
    const auto at = std::lower_bound(ids.begin(), ids.end(), *id);
    if (at == ids.end() || *at != *id) continue;
    out.emplace_back(static_cast<std::uint32_t>(i));
    shown[static_cast<std::size_t>(at - ids.begin())] = 1;
  }
  // === the nearest displayed vertex for each id none stands for
  const bool located = full.points.rows() == static_cast<Eigen::Index>(ids.size()) && full.points.cols() == 3;
  if (!located || level.restV.rows() == 0 || std::all_of(shown.begin(), shown.end(), [](char s) { return s != 0; })) {
    return out;
  }
  const NearestPointIndex nearest(level.restV);
  for (std::size_t k = 0; k < ids.size(); ++k) {
    if (shown[k] != 0) continue;
    const Eigen::Index row = nearest.nearestIndex(full.points.row(static_cast<Eigen::Index>(k)).transpose());
    if (row >= 0) out.emplace_back(static_cast<std::uint32_t>(row));
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

}  // namespace sc::spectral
