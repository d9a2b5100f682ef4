#include "model/off_reader.h"

#include <array>
#include <charconv>
#include <cmath>
#include <limits>
#include <system_error>
#include <vector>

namespace sc::model::detail {
namespace {

/// The file's lines with comments cut off, blank ones skipped, numbered from 1.
class Lines {
 public:
  explicit Lines(std::string_view bytes) : m_bytes(bytes) {}
  /// The next non-blank line (comment removed); false at the end of the file.
  bool next(std::string_view& line) {
    while (m_at < m_bytes.size()) {
      const std::size_t end = std::min(m_bytes.find('\n', m_at), m_bytes.size());
      line = m_bytes.substr(m_at, end - m_at);
      m_at = end + 1;
      ++m_number;
      line = line.substr(0, std::min(line.find('#'), line.size()));
      if (line.find_first_not_of(" \t\r\f\v") != std::string_view::npos) return true;
    }
    return false;
  }
  std::size_t number() const { return m_number; }

 private:
  std::string_view m_bytes;
  std::size_t m_at = 0;
  std::size_t m_number = 0;
};

/// Whitespace-separated numbers of one line.
class Numbers {
 public:
  explicit Numbers(std::string_view line) : m_line(line) {}
  template <class T>
  bool read(T& value) {
    const std::size_t start = m_line.find_first_not_of(" \t\r\f\v", m_at);
    if (start == std::string_view::npos) return false;
    const char* first = m_line.data() + start;
    const char* last = m_line.data() + m_line.size();
    if (*first == '+') ++first;  // from_chars takes no plus sign
    const auto [end, error] = std::from_chars(first, last, value);
    if (error != std::errc() || (end != last && std::string_view(" \t\r\f\v").find(*end) == std::string_view::npos))
      return false;
    m_at = static_cast<std::size_t>(end - m_line.data());
    return true;
  }

 private:
  std::string_view m_line;
  std::size_t m_at = 0;
};

std::string at(const Lines& lines) { return "line " + std::to_string(lines.number()) + ": "; }

/// Reads the counts line into nv, nf. @return the problem, or "".
std::string readCounts(Lines& lines, std::size_t fileBytes, std::size_t& nv, std::size_t& nf) {
  std::string_view line;
  if (!lines.next(line)) return "no vertex and face counts after the OFF keyword";
  Numbers numbers(line);
  if (!numbers.read(nv) || !numbers.read(nf)) return at(lines) + "expected the vertex and face counts";
  if (nv > fileBytes || nf > fileBytes || nv > static_cast<std::size_t>(std::numeric_limits<int>::max())) {
    return "the header declares " + std::to_string(nv) + " vertices and " + std::to_string(nf) +
           " faces, more than a file of " + std::to_string(fileBytes) + " bytes can hold";
  }
  return "";
}

std::string readVertices(Lines& lines, std::size_t nv, std::vector<std::array<double, 3>>& points) {
  points.reserve(nv);
  std::string_view line;
  for (std::size_t v = 0; v < nv; ++v) {
    if (!lines.next(line)) {
      return "the header declares " + std::to_string(nv) + " vertices but " + std::to_string(v) +
             " were read (truncated file?)";
    }
    Numbers numbers(line);
    std::array<double, 3> p{};
    if (!numbers.read(p[0]) || !numbers.read(p[1]) || !numbers.read(p[2]) || !std::isfinite(p[0]) ||
        !std::isfinite(p[1]) || !std::isfinite(p[2])) {
      return at(lines) + "vertex " + std::to_string(v) + " does not start with three finite numbers";
    }
    points.push_back(p);
  }
  return "";
}

std::string readFaces(Lines& lines, std::size_t nf, std::size_t nv, std::vector<std::array<int, 3>>& triangles) {
  triangles.reserve(nf);
  std::vector<int> corners;
  std::string_view line;
  for (std::size_t f = 0; f < nf; ++f) {
    if (!lines.next(line)) {
      return "the header declares " + std::to_string(nf) + " faces but " + std::to_string(f) +
             " were read (truncated file?)";
    }
    const std::string face = at(lines) + "face " + std::to_string(f);
    Numbers numbers(line);
    std::size_t n = 0;
    if (!numbers.read(n)) return face + " does not start with its corner count";
    if (n < 3) return face + " has " + std::to_string(n) + " corners; a face needs at least 3";
    corners.clear();
    for (std::size_t k = 0; k < n; ++k) {  // each corner is read from the line before it is stored: n is not trusted
      long long index = 0;
      if (!numbers.read(index)) return face + " declares " + std::to_string(n) + " corners but holds fewer indices";
      if (index < 0 || static_cast<unsigned long long>(index) >= nv) {
        return face + " refers to vertex index " + std::to_string(index) + " (counting from 0), but " +
               std::to_string(nv) + " vertices were read";
      }
      corners.push_back(static_cast<int>(index));
    }
    for (std::size_t k = 1; k + 1 < corners.size(); ++k) triangles.push_back({corners[0], corners[k], corners[k + 1]});
  }
  return "";
}

/// [ST][C][N]OFF, the variants whose vertex lines start with x y z.
bool isOffKeyword(std::string_view line) {
  const std::size_t start = line.find_first_not_of(" \t\r\f\v");
  std::string_view word = line.substr(start, line.find_first_of(" \t\r\f\v", start) - start);
  for (const std::string_view prefix : {"ST", "C", "N"})
    if (word.substr(0, prefix.size()) == prefix) word.remove_prefix(prefix.size());
  return word == "OFF";
}

}  // namespace

bool isBinaryOff(std::string_view bytes) {
  const std::string_view first = bytes.substr(0, bytes.find('\n'));
  return first.find("BINARY") != std::string_view::npos;
}

std::variant<TriangleSoup, std::string> readAsciiOff(std::string_view bytes) {
  Lines lines(bytes);
  std::string_view keyword;
  if (!lines.next(keyword) || !isOffKeyword(keyword)) {
    return std::string("not an OFF file this reader supports: the first line must be [ST][C][N]OFF");
  }
  std::size_t nv = 0, nf = 0;
  std::vector<std::array<double, 3>> points;
  std::vector<std::array<int, 3>> triangles;
  std::string problem = readCounts(lines, bytes.size(), nv, nf);
  if (problem.empty()) problem = readVertices(lines, nv, points);
  if (problem.empty()) problem = readFaces(lines, nf, nv, triangles);
  if (!problem.empty()) return problem;
  TriangleSoup soup;
  soup.polygonCount = nf;
  soup.V.resize(static_cast<Eigen::Index>(points.size()), 3);
  for (std::size_t v = 0; v < points.size(); ++v)
    for (int k = 0; k < 3; ++k) soup.V(static_cast<Eigen::Index>(v), k) = points[v][static_cast<std::size_t>(k)];
  soup.F.resize(static_cast<Eigen::Index>(triangles.size()), 3);
  for (std::size_t f = 0; f < triangles.size(); ++f)
    for (int k = 0; k < 3; ++k) soup.F(static_cast<Eigen::Index>(f), k) = triangles[f][static_cast<std::size_t>(k)];
  return soup;
}

}  // namespace sc::model::detail
