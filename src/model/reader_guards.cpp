#include "model/reader_guards.h"

#include <array>
#include <sstream>

namespace sc::model::detail {

bool isBinaryStl(std::istream& in, std::uintmax_t fileBytes, std::string& problem) {
  std::array<unsigned char, 84> head{};
  in.read(reinterpret_cast<char*>(head.data()), static_cast<std::streamsize>(head.size()));
  const auto got = static_cast<std::size_t>(in.gcount());
  in.clear();
  in.seekg(0);
  std::uintmax_t triangles = 0;
  for (std::size_t b = 0; b < 4; ++b) triangles |= std::uintmax_t{head[80 + b]} << (8 * b);
  const std::uintmax_t binaryBytes = 84 + 50 * triangles;
  if (got == head.size() && binaryBytes == fileBytes) return true;

  const std::string text(head.begin(), head.begin() + static_cast<std::ptrdiff_t>(got));
  const std::size_t start = text.find_first_not_of(" \t\r\n");
  if (start != std::string::npos && text.compare(start, 5, "solid") == 0) return false;
  problem = got < head.size() ? "too short for a binary STL and not an ASCII STL (no leading 'solid')"
                              : "not an ASCII STL (no leading 'solid') and not a complete binary STL: its header "
                                "declares " +
                                    std::to_string(triangles) + " triangles (" + std::to_string(binaryBytes) +
                                    " bytes) but the file has " + std::to_string(fileBytes) + " bytes";
  return false;
}

bool hasEndsolid(std::istream& in, std::uintmax_t fileBytes) {
  constexpr std::uintmax_t kTail = 512;
  in.seekg(static_cast<std::streamoff>(fileBytes > kTail ? fileBytes - kTail : 0));
  std::string tail(kTail, '\0');
  in.read(tail.data(), static_cast<std::streamsize>(tail.size()));
  tail.resize(static_cast<std::size_t>(in.gcount()));
  in.clear();
  in.seekg(0);
  return tail.find("endsolid") != std::string::npos;
}

std::string checkOffHeaderLine(std::istream& in) {
  std::string line;
  std::getline(in, line);
  in.clear();
  in.seekg(0);
  std::istringstream words(line);
  std::string magic;
  std::string rest;
  words >> magic;
  if (words >> rest && rest != "BINARY") {
    return "the OFF header line must hold only its keyword (and BINARY); put the counts on the next line";
  }
  return "";
}

ObjScan scanObj(std::istream& in) {
  ObjScan scan;
  std::string line;
  std::string word;
  for (std::size_t lineNumber = 1; std::getline(in, line); ++lineNumber) {
    std::istringstream words(line);
    if (!(words >> word)) continue;
    if (word == "v") ++scan.vertexLines;
    if (word == "mtllib") {
      std::getline(words, word);
      const std::size_t first = word.find_first_not_of(" \t\r\n");
      const std::size_t last = word.find_last_not_of(" \t\r\n");
      scan.materialFiles.push_back(first == std::string::npos ? "" : word.substr(first, last - first + 1));
    }
    if (word != "f" || !scan.problem.empty()) continue;
    while (words >> word) {
      // OpenMesh's OBJ reader asserts (and so aborts) on a corner without its vertex index, such as "/2".
      if (word.front() == '/') {
        scan.problem = "line " + std::to_string(lineNumber) + ": face corner '" + word + "' has no vertex index";
        break;
      }
    }
  }
  in.clear();
  in.seekg(0);
  return scan;
}

std::string checkObjMaterialFiles(const std::filesystem::path& objPath, const std::vector<std::string>& names) {
  // OpenMesh prefixes each name with the OBJ's path up to its last '/', or with "./".
  const std::string file = objPath.string();
  const std::size_t slash = file.find_last_of('/');
  const std::string folder = slash == std::string::npos ? "./" : file.substr(0, slash + 1);
  for (const std::string& name : names) {
    std::error_code error;
    const auto status = std::filesystem::status(folder + name, error);
    if (std::filesystem::exists(status) && !std::filesystem::is_regular_file(status)) {
      return "its material library '" + name + "' is not a regular file";
    }
  }
  return "";
}

std::string checkPlyHeader(std::istream& in, std::uintmax_t fileBytes) {
  std::string line;
  std::getline(in, line);
  const std::size_t end = line.find_last_not_of(" \t\r");
  line.resize(end == std::string::npos ? 0 : end + 1);
  std::string problem;
  if (line != "ply" && line != "PLY") problem = "not a PLY file: the first line must be 'ply'";
  // The same reads, in the same order and with the same types, as OpenMesh's _PLYReader_::can_u_read().
  std::string keyword;
  std::string word;
  float version = 0;
  bool readable = problem.empty() && (in >> keyword >> word >> version);
  bool haveElement = false;
  while (readable && problem.empty() && (in >> keyword) && keyword != "end_header") {
    if (keyword == "comment") {
      readable = static_cast<bool>(std::getline(in, line));
    } else if (keyword == "element") {
      unsigned int count = 0;
      readable = static_cast<bool>(in >> word >> count);
      haveElement = true;
      if (readable && count > fileBytes) {
        problem = "element '" + word + "' declares " + std::to_string(count) + " items, more than a file of " +
                  std::to_string(fileBytes) + " bytes can hold";
      }
    } else if (keyword == "property") {
      if (!haveElement) problem = "PLY header declares a property before any element";
      readable = static_cast<bool>(in >> word);
      readable =
          readable && (word == "list" ? static_cast<bool>(in >> word >> word >> word) : static_cast<bool>(in >> word));
    }
  }
  if (problem.empty() && (!readable || keyword != "end_header")) {
    problem = "malformed PLY header: it is unreadable or has no 'end_header'";
  }
  in.clear();
  in.seekg(0);
  return problem;
}

}  // namespace sc::model::detail
