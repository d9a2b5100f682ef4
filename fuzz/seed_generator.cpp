// Writes the seed corpora of the fuzz targets (fuzz/corpus/<target>/seed-*) from the project's own encoders, so
// every seed is a valid (or, for the modes that append a tag or checksum, a valid-once-completed) encoding.
// Usage: shapecast_fuzz_seeds <corpus folder>   (run once by hand; the seeds are kept in the repository).
// The mode byte in front of each seed is the one the target's header comment documents.

#include "fuzz_support.h"
#include "mesh_files.h"
#include "model/session_file.h"
#include "model/session_file_v1.h"
#include "session/wire/coefficient_codec.h"
#include "session/wire/control_messages.h"
#include "session/wire/level_codec.h"
#include "session/wire/model_transfer.h"
#include "session/wire/path_open.h"
#include "spectral/basis_cache.h"
#include "spectral/resolution_level.h"
#include "test_levels.h"
#include "test_meshes.h"

#include <Eigen/Geometry>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

namespace {

using namespace sc::session;
namespace fs = std::filesystem;

/// Writes one seed: the mode byte, then `bytes`.
class SeedWriter {
 public:
  SeedWriter(const fs::path& root, const char* target) : m_folder(root / target) { fs::create_directories(m_folder); }
  void write(const std::string& name, std::uint8_t mode, std::string_view bytes) const {
    std::ofstream out(m_folder / ("seed-" + name), std::ios::binary | std::ios::trunc);
    out.put(static_cast<char>(mode));
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  }
  void write(const std::string& name, std::uint8_t mode, const QByteArray& bytes) const {
    write(name, mode, std::string_view(bytes.constData(), static_cast<std::size_t>(bytes.size())));
  }

 private:
  fs::path m_folder;
};

QByteArray key() {
  const auto bytes = sc::fuzz::fixedKey();
  return QByteArray(reinterpret_cast<const char*>(bytes.data()), static_cast<qsizetype>(bytes.size()));
}

QByteArray filled(int size, char seed) {
  QByteArray bytes(size, '\0');
  for (int i = 0; i < size; ++i) bytes[i] = static_cast<char>(seed + 7 * i);
  return bytes;
}

Eigen::MatrixXd coefficients(int m) {
  Eigen::MatrixXd Z(m, 3);
  for (int i = 0; i < m; ++i)
    for (int c = 0; c < 3; ++c) Z(i, c) = std::sin(3 * i + c) * std::pow(0.9, i);
  return Z;
}

void datagramSeeds(const fs::path& root) {
  const SeedWriter seeds(root, "datagram");
  struct Layout {
    const char* name;
    int m;
    CodecOptions options;
  };
  const Layout layouts[] = {{"m100", 100, {}}, {"m5-p0-b1", 5, {1, 0, 1}}, {"m100-p3", 100, {3, 4, 7}}};
  for (const Layout& layout : layouts) {
    CoefficientEncoder encoder(key(), sc::fuzz::kFixedPeer, layout.options);
    const std::vector<QByteArray> parts = encoder.encodeFrame(11, coefficients(layout.m), 12345);
    for (std::size_t j = 0; j < parts.size() && j < 2; ++j) {
      const std::string name = std::string(layout.name) + "-part" + std::to_string(j);
      seeds.write(name + "-full", 0, parts[j]);
      const std::optional<QByteArray> clear =
          openCoefficientDatagram(key(), encoder.nextSequence() - parts.size() + j, parts[j]);
      if (clear) seeds.write(name + "-body", 1, *clear);
    }
  }
  const QByteArray pathOpen = encodePathOpen(sc::fuzz::kFixedPeer, QByteArray(kPathTokenSize, '\x5a'), 1, key());
  seeds.write("path-open-full", 2, pathOpen);
  seeds.write("path-open-body", 3, pathOpen.first(pathOpen.size() - kTagSize));
  const DatagramMac mac(key());
  const QByteArray challenge =
      encodePathProbe(MessageType::PathChallenge, sc::fuzz::kFixedPeer, 0x0123456789abcdefu, mac);
  const QByteArray response = encodePathProbe(MessageType::PathResponse, sc::fuzz::kFixedPeer, 42, mac);
  seeds.write("path-challenge-full", 4, challenge);
  seeds.write("path-response-full", 4, response);
  seeds.write("path-response-body", 5, response.first(response.size() - kTagSize));
}

/// A small level: an icosahedron, P mapping vertex i to full-resolution vertices i and (i + 1) mod n, K n by 4.
sc::spectral::ResolutionLevel smallLevel() {
  const auto n = static_cast<int>(sc::testing::icosphere(0).V.rows());
  return sc::testing::icosphereLevel(0, Eigen::MatrixXd::Random(n, 4));
}

QByteArray levelBytes() {
  const std::vector<std::byte> bytes = sc::spectral::encodeResolutionLevel(smallLevel());
  return QByteArray(reinterpret_cast<const char*>(bytes.data()), static_cast<qsizetype>(bytes.size()));
}

void levelSeeds(const fs::path& root) {
  const SeedWriter seeds(root, "level");
  const QByteArray level = levelBytes();
  seeds.write("icosahedron-full", 0, level);
  seeds.write("icosahedron-body", 1, level.first(level.size() - 8));
  // Compressed (mode 2): as a host sends it since protocol version 6, and with each section cut short.
  const QByteArray compressed = compressLevelPayload(level);
  seeds.write("icosahedron-compressed", 2, compressed);
  seeds.write("icosahedron-compressed-cut", 2, compressed.first(compressed.size() - 5));
}

QByteArray frames(const std::vector<ControlMessage>& messages) {
  QByteArray stream;
  for (const ControlMessage& message : messages) stream += encodeControlMessage(message);
  return stream;
}

void controlSeeds(const fs::path& root) {
  const SeedWriter seeds(root, "control");
  HandleTransform handle{7, {1, 0, 0, 0.25, 0, 1, 0, -0.5, 0, 0, 1, 1e-300}};
  const std::vector<ControlMessage> samples{
      Hello{kProtocolVersion, QString::fromUtf8("Zoë 🦆")},
      Refused{RefuseReason::VersionMismatch, kProtocolVersion, QStringLiteral("host speaks version 1, you 2")},
      Challenge{filled(kNonceSize, 1), filled(kSaltSize, 2), 1},
      ChallengeResponse{filled(kMacSize, 3)},
      Welcome{3, filled(kDatagramKeySize, 4), filled(kPathTokenSize, 5), 100, 1000, 4000},
      ModelBegin{9, TransferKind::Level, 5000, 300, filled(kChecksumSize, 6)},
      ModelChunk{9, 0, 300, filled(100, 8)},
      ResolutionRequest{5000},
      PeerList{{{1, 22982, QStringLiteral("host")}, {2, 5000, QString()}}},
      LockMessage{LockRequestKind::Renew, 42},
      LockNotice{LockNoticeKind::Released, 3, 42, 0, LockReleaseReason::LeaseExpired},
      Drag{42, {handle, HandleTransform{}}},
      Keyframe{123456, {0.5, -0.25, 1e-3, 2, 3, 4}},
      Leave{},
      Heartbeat{0xfffffffe},
      Constraints{42, {{1, 2, 3}, {22981}}, {7, 8}},
      StatsReport{5000, 90, 180, 20, 3, 1, 0.1, 0.5, 24.2, 30.1, 30.0, 0.2, 1.5, 0.12, 0.01, 0.0},
      LevelList{3, {{0, 1000, 1996, 50000}, {2, 100, 196, 5000}}},
      StrokeEnd{42},
      EditRequest{EditAction::Undo},
      EditLog{{{1, 1, 0, false, QStringLiteral("host")}, {2, 3, 1, true, QString::fromUtf8("Zoë")}}},
      LockNotice{LockNoticeKind::Refused, 3, 42, 0, LockReleaseReason::Released, {2, 4}},
      Presence{
          3, {1.0, 2.0, 3.0}, {0.0, 0.0, 0.0}, {0.0, 1.0, 0.0}, true, {0.5, 0.5, 0.5}, true, true, {0.25, 0.5, 0.75}},
  };
  for (const ControlMessage& message : samples) {
    char name[16];
    std::snprintf(name, sizeof name, "type-%02x", static_cast<unsigned>(messageType(message)));
    seeds.write(name, 0, frames({message}));
  }
  // Whole conversations, delivered at once and in small chunks.
  const QByteArray join = frames({Hello{kProtocolVersion, QStringLiteral("fuzz")},
                                  ChallengeResponse{filled(kMacSize, 9)}, ResolutionRequest{0}, Heartbeat{1}, Leave{}});
  seeds.write("client-stream", 0, join);
  seeds.write("client-stream-split7", 7, join);
  const QByteArray level = levelBytes();
  const auto size = static_cast<std::uint32_t>(level.size());
  const auto half = static_cast<std::uint32_t>(level.size() / 2);
  const QByteArray welcome =
      frames({Challenge{filled(kNonceSize, 1), filled(kSaltSize, 2), 1},
              Welcome{3, filled(kDatagramKeySize, 4), filled(kPathTokenSize, 5), 100, 1000, 4000},
              ModelBegin{1, TransferKind::Level, 12, size, sha256(level)}, ModelChunk{1, 0, size, level.first(half)},
              ModelChunk{1, half, size, level.sliced(half)}});
  seeds.write("host-stream", 0, welcome);
  seeds.write("host-stream-split13", 13, welcome);
}

void basisCacheSeeds(const fs::path& root) {
  const SeedWriter seeds(root, "basis_cache");
  sc::spectral::HarmonicBasis basis;
  basis.eigenvalues = Eigen::VectorXd::LinSpaced(3, 0.0, 2.0);
  basis.vectors = Eigen::MatrixXd::Random(5, 3);
  basis.shift = -0.01;
  const fs::path file = fs::temp_directory_path() / "shapecast-fuzz-seed.mhb";
  if (!sc::spectral::writeBasisCache(file, {0x0123456789abcdefULL, 5, 3, -0.01}, basis)) return;
  std::ifstream in(file, std::ios::binary);
  const std::string bytes{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  fs::remove(file);
  seeds.write("n5-m3-full", 0, bytes);
  seeds.write("n5-m3-body", 1, std::string_view(bytes).substr(0, bytes.size() - 8));
  seeds.write("n5-m3-other-key", 2, bytes);
  // An empty basis (m = 0): its null data() once reached memcpy (found by the sanitisers, fixed in basis_cache.cpp).
  sc::spectral::HarmonicBasis empty;
  empty.vectors.resize(5, 0);
  if (!sc::spectral::writeBasisCache(file, {0x0123456789abcdefULL, 5, 0, -0.01}, empty)) return;
  std::ifstream emptyIn(file, std::ios::binary);
  seeds.write("n5-m0-full", 0, std::string{std::istreambuf_iterator<char>(emptyIn), std::istreambuf_iterator<char>()});
  fs::remove(file);
}

/// Sessions of a small torus: version 2 without and with current constraints and edit steps (named, unnamed,
/// undone), each whole (mode 0) and as a payload to be sealed (mode 1); version 1 with a current state and a history
/// whose states share their lists ("same as previous"), whole and as a payload (mode 3), so the legacy reader stays
/// fuzzed.
void sessionFileSeeds(const fs::path& root) {
  const SeedWriter seeds(root, "session_file");
  const sc::testing::GeneratedMesh mesh = sc::testing::torus(8, 6);
  sc::model::SessionFile file;
  file.V = mesh.V;
  file.F = mesh.F;
  file.m = 6;
  file.Z = coefficients(file.m);
  const auto payload = [](const QByteArray& bytes) { return bytes.mid(20, bytes.size() - 20 - 32); };
  const QByteArray plain = sc::model::encodeSessionFile(file);
  seeds.write("torus-plain", 0, plain);
  seeds.write("torus-plain-payload", 1, payload(plain));

  file.mode = sc::spectral::DeformationMode::Rigid;
  file.current = sc::model::SavedConstraints{{0, 1, 2}, {20, 21, 22, 23, 30}};
  file.steps = {{QStringLiteral("Alice"), 0.1 * coefficients(file.m), false},
                {QString::fromUtf8("Zoë"), -0.05 * coefficients(file.m), false},
                {QString(), 0.2 * coefficients(file.m), true}};
  const QByteArray steps = sc::model::encodeSessionFile(file);
  seeds.write("torus-steps", 0, steps);
  seeds.write("torus-steps-payload", 1, payload(steps));

  sc::model::v1::SavedDeformation rest;
  rest.handle = {0, 1, 2};
  rest.anchors = {20, 21, 22, 23, 30};
  sc::model::v1::SavedDeformation moved = rest;
  moved.translation = Eigen::Vector3d(0.1, 0.2, -0.1);
  sc::model::v1::SavedDeformation turned = moved;
  turned.rotation = Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  sc::model::v1::SavedDeformation other;
  other.handle = {5};
  other.anchors = {40, 41};
  sc::model::v1::LegacySessionFile legacy;
  legacy.V = file.V;
  legacy.F = file.F;
  legacy.m = file.m;
  legacy.mode = file.mode;
  legacy.Z = file.Z;
  legacy.current = turned;
  legacy.history = {{rest, moved}, {moved, turned}, {turned, other}};
  legacy.historyIndex = 2;
  const QByteArray history = sc::model::v1::encodeLegacySessionFile(legacy);
  seeds.write("torus-v1-history", 0, history);
  seeds.write("torus-v1-history-payload", 3, payload(history));
  // An anchor list longer than the mesh (ids repeated), repeated by every later state: refused as it is read
  // (issue 14; before, such lists were copied for every "same as previous" before any check).
  for (int i = 0; i < 2 * static_cast<int>(legacy.V.rows()); ++i) other.anchors.push_back(i % 40);
  legacy.history.back().after = other;
  legacy.history.push_back({other, other});
  seeds.write("torus-v1-long-list", 0, sc::model::v1::encodeLegacySessionFile(legacy));
}

void meshSeeds(const fs::path& root) {
  using sc::testing::FileFormat;
  const SeedWriter seeds(root, "mesh");
  const sc::testing::GeneratedMesh mesh = sc::testing::icosphere(0);
  const struct {
    FileFormat format;
    std::uint8_t mode;
  } formats[] = {{FileFormat::Off, 0},       {FileFormat::Obj, 1},      {FileFormat::PlyAscii, 2},
                 {FileFormat::PlyBinary, 2}, {FileFormat::StlAscii, 3}, {FileFormat::StlBinary, 3}};
  for (const auto& [format, mode] : formats)
    seeds.write(std::string("icosahedron-") + sc::testing::nameOf(format), mode,
                sc::testing::meshBytes(mesh.V, mesh.F, format));
  // Polygons, negative and slashed OBJ indices, PLY with extra properties.
  seeds.write("quad-off", 0, std::string_view("OFF\n5 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n4 0 1 2 3\n3 0 1 4\n"));
  seeds.write("slashes-obj", 1,
              std::string_view("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nvt 0 0\nvn 0 0 1\n"
                               "f 1/1/1 2/1/1 3/1/1\nf -4//1 -3//1 -1//1\n"));
  seeds.write("properties-ply", 2,
              std::string_view("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                               "property float z\nproperty uchar red\nelement face 1\n"
                               "property list uchar int vertex_indices\nend_header\n0 0 0 255\n1 0 0 0\n0 1 0 9\n"
                               "3 0 1 2\n"));
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s <corpus folder>\n", argv[0]);
    return 2;
  }
  const fs::path root = argv[1];
  datagramSeeds(root);
  controlSeeds(root);
  levelSeeds(root);
  basisCacheSeeds(root);
  meshSeeds(root);
  sessionFileSeeds(root);
  return 0;
}
