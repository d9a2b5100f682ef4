#pragma once
// Internal to the session file (session_file.h): its vertex id lists — the host user's handle and anchors — as
// written, read, checked and (for version 1) expanded. Full-resolution vertex ids as plain ints (the app converts
// its typed ids). Cost: O(ids) for everything here.

#include "model/session_file_codec.h"
#include "model/session_file_content.h"

#include <QString>

#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

namespace sc::model::detail {

/// Version 2's id list: u32 count, count × u32 ids (ascending).
void writeIdList(ByteWriter& out, const std::vector<int>& ids);

/// Reads writeIdList()'s bytes. A count over `vertices` (the mesh's #V) is refused before anything is allocated
/// (no valid list is longer), as is one larger than the data left; an id over INT_MAX becomes −1 (validation names
/// it). Empty after a failure (in.ok() false).
[[nodiscard]] std::vector<int> readIdList(ByteReader& in, std::uint32_t vertices, const char* what);

/// Empty when `ids` is a usable constraint set of a mesh with `n` vertices: a non-empty handle, every id in
/// 0..n−1, both lists ascending without repeats, no id in both. Else the problem, prefixed with `what`.
[[nodiscard]] QString validateConstraintIds(const SavedConstraints& ids, int n, const QString& what);

/// `handle` and `anchors` as a SavedConstraints: each sorted without repeats, the anchors without the handle's ids
/// (version 1 stored the lists in the app's order, anchors were not guaranteed sorted).
[[nodiscard]] SavedConstraints normalisedConstraints(std::vector<int> handle, std::vector<int> anchors);

// ---------------------------------------------------------------------------------------------------- version 1

/// Version 1's id list: u8 0 = "the same as the previous list of this kind", or u8 1, u32 count, count × u32 ids.
/// Writes `ids` as "the same" when equal to `previous`; `previous` becomes `ids`.
void writeLegacyIdList(ByteWriter& out, const std::vector<int>& ids, std::optional<std::vector<int>>& previous);

/// A version-1 list as read: shared by every "same as previous" reference to it (nothing is copied while parsing).
using SharedIdList = std::shared_ptr<const std::vector<int>>;

/// Reads the version-1 lists of one file, checked as they are read, before anything is expanded: an explicit list
/// holds at most as many ids as the mesh has vertices, and every list, explicit or "the same as the previous one",
/// is counted against kMaxSessionFileIds. Expanding every list returned (copying it) therefore costs at most
/// kMaxSessionFileIds ids of memory.
class LegacyIdListReader {
 public:
  explicit LegacyIdListReader(std::uint32_t vertices) : m_vertices(vertices) {}

  /// The next list; `previous` is the last list of this kind (handle or anchors) and becomes this one. Null after
  /// a failure (in.ok() false).
  SharedIdList read(ByteReader& in, SharedIdList& previous, const char* what);

 private:
  bool spend(ByteReader& in, std::uint64_t count);

  std::uint32_t m_vertices = 0;
  std::uint64_t m_ids = 0;  ///< ids in all lists so far, "same as previous" ones counted again
};

/// A shared list's copy (empty for null).
[[nodiscard]] std::vector<int> expanded(const SharedIdList& list);

}  // namespace sc::model::detail
