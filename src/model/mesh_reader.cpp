#include "model/mesh_reader.h"

#include "model/off_reader.h"
#include "model/reader_guards.h"
#include "model/soup_importer.h"

#include <OpenMesh/Core/IO/reader/OBJReader.hh>
#include <OpenMesh/Core/IO/reader/OFFReader.hh>
#include <OpenMesh/Core/IO/reader/PLYReader.hh>
#include <OpenMesh/Core/IO/reader/STLReader.hh>
#include <OpenMesh/Core/System/omstream.hh>

#include <algorithm>
#include <cctype>
#include <fstream>
#include <iterator>
#include <mutex>
#include <string>
#include <utility>

namespace sc::model::detail {
namespace {

/// Mutes OpenMesh's log streams (omerr, omlog, omout) while alive and then restores their previous state.
class MutedOpenMeshLogs {
 public:
  MutedOpenMeshLogs() : m_err(::omerr().is_enabled()), m_log(::omlog().is_enabled()), m_out(::omout().is_enabled()) {
    ::omerr().disable();
    ::omlog().disable();
    ::omout().disable();
  }
  ~MutedOpenMeshLogs() {
    if (m_err) ::omerr().enable();
    if (m_log) ::omlog().enable();
    if (m_out) ::omout().enable();
  }
  MutedOpenMeshLogs(const MutedOpenMeshLogs&) = delete;
  MutedOpenMeshLogs& operator=(const MutedOpenMeshLogs&) = delete;

 private:
  bool m_err;
  bool m_log;
  bool m_out;
};

/// What to tell OpenMesh and what to check afterwards, found by looking at the file before it reads.
struct ReadPlan {
  MeshFormat format = MeshFormat::Off;
  bool binaryStl = false;
  std::size_t objVertexLines = 0;  ///< OBJ only: "v" lines in the file.
  /// OBJ and ASCII STL readers loop until their stream fails; every other reader must leave it good.
  bool streamMustStayGood() const { return format == MeshFormat::Off || format == MeshFormat::Ply || binaryStl; }
};

/// Runs the reader guards on the file (see reader_guards.h) and rewinds it. @return the problem, or "".
std::string planRead(const std::filesystem::path& path, MeshFormat format, std::istream& in, std::uintmax_t fileBytes,
                     ReadPlan& plan) {
  plan.format = format;
  std::string problem;
  if (format == MeshFormat::Stl) {
    plan.binaryStl = isBinaryStl(in, fileBytes, problem);
    if (problem.empty() && !plan.binaryStl && !hasEndsolid(in, fileBytes)) {
      problem = "ASCII STL without its closing 'endsolid' (truncated file?)";
    }
  }
  if (format == MeshFormat::Obj) {
    ObjScan scan = scanObj(in);
    plan.objVertexLines = scan.vertexLines;
    problem = scan.problem.empty() ? checkObjMaterialFiles(path, scan.materialFiles) : std::move(scan.problem);
  }
  if (format == MeshFormat::Off) problem = checkOffHeaderLine(in);
  if (format == MeshFormat::Ply) problem = checkPlyHeader(in, fileBytes);
  return problem;
}

/// Runs OpenMesh's reader for the planned format on `in`. @return a description of the problem, or "".
std::string runReader(const ReadPlan& plan, const std::string& fileName, std::istream& in, SoupImporter& importer) {
  OpenMesh::IO::Options options;  // no normals, colours or texture coordinates requested
  switch (plan.format) {
    case MeshFormat::Off:  // binary OFF only (readTriangleSoup() reads ASCII OFF itself)
      // can_u_read() parses the header line and records the variant (COFF, NOFF, BINARY …) for read().
      if (!OpenMesh::IO::OFFReader().can_u_read(fileName)) {
        return "not an OFF file this reader supports: the first line must be [ST][C][N]OFF [BINARY]";
      }
      return OpenMesh::IO::OFFReader().read(in, importer, options) ? "" : "OpenMesh's OFF reader rejected it";
    case MeshFormat::Ply:
      return OpenMesh::IO::PLYReader().read(in, importer, options) ? "" : "malformed PLY header or body";
    case MeshFormat::Stl:
      if (plan.binaryStl) options += OpenMesh::IO::Options::Binary;
      return OpenMesh::IO::STLReader().read(in, importer, options) ? "" : "OpenMesh's STL reader rejected it";
    case MeshFormat::Obj:
      // By file name, so that OpenMesh resolves "mtllib" against the OBJ's folder (checkObjMaterialFiles() made
      // sure that ends). Nothing is lost: OBJ readers end on a failed stream anyway, so its state tells nothing.
      return OpenMesh::IO::OBJReader().read(fileName, importer, options) ? "" : "OpenMesh's OBJ reader rejected it";
  }
  return "unsupported format";
}

constexpr const char* kUnreadable = "the file ends early or holds a value that cannot be read (truncated or malformed)";

/// How one reader run went.
struct ReadOutcome {
  std::string readerProblem;  ///< the reader returned false: why (runReader()).
  std::string abortReason;    ///< a SoupImporter callback threw: what it said.
  bool abortedOnFailedStream = false;
  bool streamFailedAtEnd = false;
};

/// Names the first cause of failure, most fundamental first. @return the problem, or "" when the soup is sound.
std::string diagnose(const ReadPlan& plan, const SoupImporter& importer, const ReadOutcome& outcome) {
  // A failed stream explains everything after it, bad indices read from stale values included.
  if (outcome.abortedOnFailedStream || (plan.streamMustStayGood() && outcome.streamFailedAtEnd)) return kUnreadable;
  // An OBJ "v" line OpenMesh skipped shifts all later indices: report the line, not the index it broke.
  if (plan.objVertexLines > importer.vertexCount()) {
    return std::to_string(plan.objVertexLines - importer.vertexCount()) + " of its " +
           std::to_string(plan.objVertexLines) +
           " 'v' lines do not hold three readable numbers (NaN, inf, out of range or garbage)";
  }
  if (!outcome.abortReason.empty()) return outcome.abortReason;
  if (!outcome.readerProblem.empty()) return outcome.readerProblem;
  if (importer.declaredVertices() && *importer.declaredVertices() != importer.vertexCount()) {
    return "the header declares " + std::to_string(*importer.declaredVertices()) + " vertices but " +
           std::to_string(importer.vertexCount()) + " were read (truncated file?)";
  }
  if (importer.declaredFaces() && *importer.declaredFaces() != importer.polygonCount()) {
    return "the header declares " + std::to_string(*importer.declaredFaces()) + " faces but " +
           std::to_string(importer.polygonCount()) + " were read (truncated file?)";
  }
  return "";
}

}  // namespace

std::optional<MeshFormat> formatFromExtension(const std::filesystem::path& path) {
  std::string extension = path.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (extension == ".off") return MeshFormat::Off;
  if (extension == ".obj") return MeshFormat::Obj;
  if (extension == ".ply") return MeshFormat::Ply;
  if (extension == ".stl") return MeshFormat::Stl;
  return std::nullopt;
}

std::variant<TriangleSoup, MeshError> readTriangleSoup(const std::filesystem::path& path, MeshFormat format,
                                                       std::uintmax_t fileBytes) {
  const auto fail = [&path](const std::string& problem) {
    return MeshError{MeshErrorKind::ReadFailed, "cannot read '" + path.string() + "': " + problem};
  };
  std::ifstream in(path, std::ios::in | std::ios::binary);
  if (!in) return fail("the file cannot be opened");
  ReadPlan plan;
  if (const std::string problem = planRead(path, format, in, fileBytes, plan); !problem.empty()) return fail(problem);
  if (format == MeshFormat::Off) {  // ASCII OFF by our own reader (doubles, comments); binary OFF by OpenMesh's
    const std::string bytes{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
    if (!isBinaryOff(bytes)) {
      auto read = readAsciiOff(bytes);
      if (auto* problem = std::get_if<std::string>(&read)) return fail(*problem);
      return std::move(std::get<TriangleSoup>(read));
    }
    in.clear();
    in.seekg(0);
  }

  static std::mutex openMeshReaders;  // OpenMesh's readers are singletons that keep per-read state
  const std::lock_guard lock(openMeshReaders);
  const MutedOpenMeshLogs muted;
  SoupImporter importer(in, fileBytes);
  ReadOutcome outcome;
  // Readers that read exact counts get a stream that throws on its first failed read: otherwise they go on with
  // stale values, and a corrupt corner count (say 4e9) makes them push that many handles before any callback.
  if (plan.streamMustStayGood()) in.exceptions(std::ios::failbit | std::ios::badbit);
  try {
    outcome.readerProblem = runReader(plan, path.string(), in, importer);
  } catch (const ImportAborted& aborted) {
    outcome.abortReason = aborted.what();
    outcome.abortedOnFailedStream = in.fail();  // the exception left the reader at once: this is its state then
  } catch (const std::exception&) {
    if (!in.fail()) throw;  // not the stream's (std::ios_base::failure is caught by its base: ABI-proof)
    outcome.abortedOnFailedStream = true;
  }
  in.exceptions(std::ios::goodbit);
  outcome.streamFailedAtEnd = in.fail();
  if (const std::string problem = diagnose(plan, importer, outcome); !problem.empty()) return fail(problem);

  TriangleSoup soup;
  soup.polygonCount = importer.polygonCount();
  importer.takeSoup(soup.V, soup.F);
  return soup;
}

}  // namespace sc::model::detail
