#pragma once
// Private to shapecast_model: checks made on a mesh file before OpenMesh's readers see it. Each one keeps a
// reader out of a failure mode it cannot report itself: guessing wrong (STL encoding), silently wrong data (an
// OBJ vertex line it skips, an ASCII STL cut short, an OFF header it misreads), or not returning at all (a PLY
// header it loops on forever, an OBJ face it asserts on). Every function reads from the start of `in` and
// rewinds it (clearing its state) before returning. No OpenMesh here.

#include <cstdint>
#include <filesystem>
#include <istream>
#include <string>
#include <vector>

namespace sc::model::detail {

/// Whether an STL file is binary: an 80-byte header, a little-endian uint32 triangle count n and exactly n records
/// of 50 bytes. Anything else that starts with "solid" is ASCII. OpenMesh's stream reader must be told which.
/// @param[out] problem  set when the file is neither, else left empty.
/// @return true for binary, false for ASCII (or neither).
/// Cost: O(1).
bool isBinaryStl(std::istream& in, std::uintmax_t fileBytes, std::string& problem);

/// Whether an ASCII STL is complete: its last 512 bytes hold the closing "endsolid". (OpenMesh silently drops a
/// facet cut short.) Cost: O(1).
bool hasEndsolid(std::istream& in, std::uintmax_t fileBytes);

/// Checks the first line of an OFF file: OpenMesh expects only the keyword ([ST][C][N]OFF, optionally BINARY) and
/// would misread counts placed on the same line. @return the problem, or "". Cost: O(first line).
std::string checkOffHeaderLine(std::istream& in);

/// What a pre-scan of an OBJ file finds, with lines split into words the way OpenMesh's reader splits them.
struct ObjScan {
  /// "v" lines. OpenMesh skips one whose numbers do not parse (NaN, inf, garbage), which silently shifts every
  /// later index: comparing this count with the vertices the reader delivered detects that.
  std::size_t vertexLines = 0;
  std::string problem;  ///< a face corner without vertex index ("/2"): OpenMesh's reader asserts and aborts on it.
  std::vector<std::string> materialFiles;  ///< the names after each "mtllib", trimmed as OpenMesh trims them.
};

/// Scans an OBJ file. Cost: one pass over the file.
ObjScan scanObj(std::istream& in);

/// Checks the material files an OBJ names: OpenMesh's reader opens each one relative to the OBJ's folder and
/// reads it to its end, so one that exists but is not a regular file ("mtllib /dev/zero") would never return.
/// Missing material files are fine (OpenMesh skips them). @return the problem, or "". Cost: one stat per name.
std::string checkObjMaterialFiles(const std::filesystem::path& objPath, const std::vector<std::string>& names);

/// Replays OpenMesh's word-by-word PLY header parse and accepts only a header it will get through: OpenMesh loops
/// forever on a header without "end_header" or with an unreadable word (growing memory without bound when the
/// last word was "element"), and indexes an empty list on a "property" before any "element". Also rejects an
/// element count larger than the file (each element takes at least one byte).
/// @return the problem, or "". Cost: O(header size), or one pass over a file without "end_header".
std::string checkPlyHeader(std::istream& in, std::uintmax_t fileBytes);

}  // namespace sc::model::detail
