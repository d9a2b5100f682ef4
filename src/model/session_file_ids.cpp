#include "model/session_file_ids.h"

#include <algorithm>
#include <iterator>
#include <limits>
#include <utility>

namespace sc::model::detail {

namespace {

int idOf(std::uint32_t v) {
  return v > static_cast<std::uint32_t>(std::numeric_limits<int>::max()) ? -1 : static_cast<int>(v);
}

/// Reads `count` ids into a new vector (the caller checked that they fit).
std::vector<int> readIds(ByteReader& in, std::uint32_t count) {
  std::vector<int> ids(count);
  for (int& id : ids) id = idOf(in.u32());
  return ids;
}

/// Refuses a list count over the mesh's vertex count or over the data left.
bool countFits(ByteReader& in, std::uint32_t count, std::uint32_t vertices, const char* what) {
  if (in.ok() && count > vertices) {
    in.fail(QStringLiteral("a %1 list has %2 ids, more than the mesh's %3 vertices")
                .arg(QLatin1StringView(what))
                .arg(count)
                .arg(vertices));
    return false;
  }
  return in.fits(count, 4, what);
}

void sortUnique(std::vector<int>& ids) {
  std::sort(ids.begin(), ids.end());
  ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
}

}  // namespace

void writeIdList(ByteWriter& out, const std::vector<int>& ids) {
  out.u32(static_cast<std::uint32_t>(ids.size()));
  for (int id : ids) out.u32(static_cast<std::uint32_t>(id));
}

std::vector<int> readIdList(ByteReader& in, std::uint32_t vertices, const char* what) {
  const std::uint32_t count = in.u32();
  if (!countFits(in, count, vertices, what)) return {};
  return readIds(in, count);
}

QString validateConstraintIds(const SavedConstraints& ids, int n, const QString& what) {
  if (ids.handle.empty()) return QStringLiteral("%1 has an empty handle").arg(what);
  for (const auto& [list, name] : {std::pair{&ids.handle, "handle"}, std::pair{&ids.anchors, "anchor"}}) {
    for (std::size_t i = 0; i < list->size(); ++i) {
      const int id = (*list)[i];
      if (id < 0 || id >= n) {
        return QStringLiteral("%1 has %2 vertex id %3, outside 0..%4")
            .arg(what, QLatin1StringView(name))
            .arg(id)
            .arg(n - 1);
      }
      if (i > 0 && (*list)[i - 1] >= id) {
        return QStringLiteral("%1 has %2 ids out of order or repeated (%3 after %4)")
            .arg(what, QLatin1StringView(name))
            .arg(id)
            .arg((*list)[i - 1]);
      }
    }
  }
  std::vector<int> shared;
  std::set_intersection(ids.handle.begin(), ids.handle.end(), ids.anchors.begin(), ids.anchors.end(),
                        std::back_inserter(shared));
  if (!shared.empty()) {
    return QStringLiteral("%1 has vertex %2 in both the handle and the anchors").arg(what).arg(shared.front());
  }
  return {};
}

SavedConstraints normalisedConstraints(std::vector<int> handle, std::vector<int> anchors) {
  sortUnique(handle);
  sortUnique(anchors);
  SavedConstraints out;
  out.handle = std::move(handle);
  std::set_difference(anchors.begin(), anchors.end(), out.handle.begin(), out.handle.end(),
                      std::back_inserter(out.anchors));
  return out;
}

void writeLegacyIdList(ByteWriter& out, const std::vector<int>& ids, std::optional<std::vector<int>>& previous) {
  if (previous && *previous == ids) {
    out.u8(0);
    return;
  }
  out.u8(1);
  writeIdList(out, ids);
  previous = ids;
}

SharedIdList LegacyIdListReader::read(ByteReader& in, SharedIdList& previous, const char* what) {
  const std::uint8_t kind = in.u8();
  if (!in.ok()) return {};
  if (kind == 0) {
    if (!previous) {
      in.fail(QStringLiteral("corrupted: a %1 list refers to an earlier one that is not there")
                  .arg(QLatin1StringView(what)));
      return {};
    }
    if (!spend(in, previous->size())) return {};
    return previous;
  }
  if (kind != 1) {
    in.fail(QStringLiteral("corrupted: unknown %1 list kind %2").arg(QLatin1StringView(what)).arg(kind));
    return {};
  }
  const std::uint32_t count = in.u32();
  if (!countFits(in, count, m_vertices, what) || !spend(in, count)) return {};
  auto list = std::make_shared<const std::vector<int>>(readIds(in, count));
  previous = list;
  return list;
}

bool LegacyIdListReader::spend(ByteReader& in, std::uint64_t count) {
  m_ids += count;
  if (m_ids <= static_cast<std::uint64_t>(kMaxSessionFileIds)) return true;
  in.fail(QStringLiteral("its constraint lists expand to more than %1 vertex ids").arg(kMaxSessionFileIds));
  return false;
}

std::vector<int> expanded(const SharedIdList& list) { return list ? *list : std::vector<int>{}; }

}  // namespace sc::model::detail
