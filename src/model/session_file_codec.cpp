#include "model/session_file_codec.h"

#include "model/session_file_content.h"

#include <QtEndian>

#include <openssl/evp.h>

#include <algorithm>
#include <bit>
#include <cstring>
#include <limits>

namespace sc::model::detail {

void ByteWriter::u8(std::uint8_t v) { m_bytes.append(static_cast<char>(v)); }

void ByteWriter::u32(std::uint32_t v) {
  const std::uint32_t le = qToLittleEndian(v);
  m_bytes.append(reinterpret_cast<const char*>(&le), sizeof le);
}

void ByteWriter::u64(std::uint64_t v) {
  const std::uint64_t le = qToLittleEndian(v);
  m_bytes.append(reinterpret_cast<const char*>(&le), sizeof le);
}

void ByteWriter::f64(double v) { u64(std::bit_cast<std::uint64_t>(v)); }

void ByteWriter::raw(QByteArrayView bytes) { m_bytes.append(bytes); }

void ByteReader::fail(const QString& why) {
  if (m_error.isEmpty()) m_error = why;
}

bool ByteReader::fits(std::uint64_t count, std::uint64_t size, const char* what) {
  if (!ok()) return false;
  if (count > static_cast<std::uint64_t>(left()) / size) {
    fail(QStringLiteral("truncated or corrupted: %1 %2 do not fit in the remaining %3 bytes")
             .arg(count)
             .arg(QLatin1StringView(what))
             .arg(left()));
    return false;
  }
  return true;
}

bool ByteReader::need(qsizetype count) {
  if (!ok()) return false;
  if (left() < count) {
    fail(QStringLiteral("truncated: the data ends %1 bytes after the header").arg(m_at));
    return false;
  }
  return true;
}

std::uint8_t ByteReader::u8() {
  if (!need(1)) return 0;
  return static_cast<std::uint8_t>(m_data[m_at++]);
}

std::uint32_t ByteReader::u32() {
  std::uint32_t v = 0;
  if (!need(4)) return 0;
  std::memcpy(&v, m_data.data() + m_at, 4);
  m_at += 4;
  return qFromLittleEndian(v);
}

std::uint64_t ByteReader::u64() {
  std::uint64_t v = 0;
  if (!need(8)) return 0;
  std::memcpy(&v, m_data.data() + m_at, 8);
  m_at += 8;
  return qFromLittleEndian(v);
}

double ByteReader::f64() { return std::bit_cast<double>(u64()); }

QByteArrayView ByteReader::raw(qsizetype count) {
  if (!need(count)) return {};
  const QByteArrayView out = m_data.sliced(m_at, count);
  m_at += count;
  return out;
}

QByteArray sha256(QByteArrayView bytes) {
  QByteArray digest(kSessionChecksumBytes, Qt::Uninitialized);
  unsigned int size = 0;
  if (EVP_Digest(bytes.data(), static_cast<std::size_t>(bytes.size()), reinterpret_cast<unsigned char*>(digest.data()),
                 &size, EVP_sha256(), nullptr) != 1 ||
      size != static_cast<unsigned int>(kSessionChecksumBytes)) {
    return {};
  }
  return digest;
}

QByteArray sealSessionPayload(std::uint32_t version, const QByteArray& payload) {
  ByteWriter out;
  out.raw(QByteArrayView(kSessionFileMagic, sizeof(kSessionFileMagic)));
  out.u32(version);
  out.u64(static_cast<std::uint64_t>(payload.size()));
  out.raw(payload);
  out.raw(sha256(out.bytes()));
  return std::move(out.bytes());
}

void writeMeshPart(ByteWriter& out, const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, int m,
                   spectral::DeformationMode mode) {
  out.u32(static_cast<std::uint32_t>(V.rows()));
  out.u32(static_cast<std::uint32_t>(F.rows()));
  for (Eigen::Index i = 0; i < V.rows(); ++i)
    for (Eigen::Index c = 0; c < V.cols(); ++c) out.f64(V(i, c));
  for (Eigen::Index i = 0; i < F.rows(); ++i)
    for (Eigen::Index c = 0; c < F.cols(); ++c) out.u32(static_cast<std::uint32_t>(F(i, c)));
  out.u32(static_cast<std::uint32_t>(m));
  out.u8(mode == spectral::DeformationMode::Rigid ? 1 : 0);
}

std::uint32_t readMeshPart(ByteReader& in, Eigen::MatrixXd& V, Eigen::MatrixXi& F, int& m,
                           spectral::DeformationMode& mode) {
  const std::uint32_t vertices = in.u32();
  const std::uint32_t faces = in.u32();
  if (in.fits(vertices, 24, "vertices")) {
    V.resize(vertices, 3);
    for (Eigen::Index i = 0; i < V.rows(); ++i)
      for (int c = 0; c < 3; ++c) V(i, c) = in.f64();
  }
  if (in.fits(faces, 12, "faces")) {
    F.resize(faces, 3);
    for (Eigen::Index i = 0; i < F.rows(); ++i) {
      for (int c = 0; c < 3; ++c) {
        const std::uint32_t v = in.u32();
        F(i, c) = v >= vertices ? -1 : static_cast<int>(v);  // validateMeshPart() names it
      }
    }
  }
  m = static_cast<int>(std::min<std::uint32_t>(in.u32(), std::numeric_limits<int>::max()));
  const std::uint8_t modeByte = in.u8();
  if (modeByte > 1) in.fail(QStringLiteral("unknown deformation mode %1").arg(modeByte));
  mode = modeByte == 1 ? spectral::DeformationMode::Rigid : spectral::DeformationMode::Linear;
  return vertices;
}

void writeMatrix(ByteWriter& out, const Eigen::MatrixXd& Z) {
  out.u32(static_cast<std::uint32_t>(Z.rows()));
  out.u32(static_cast<std::uint32_t>(Z.cols()));
  for (Eigen::Index r = 0; r < Z.rows(); ++r)
    for (Eigen::Index c = 0; c < Z.cols(); ++c) out.f64(Z(r, c));
}

void readMatrix(ByteReader& in, Eigen::MatrixXd& Z, const char* what) {
  const std::uint32_t rows = in.u32();
  const std::uint32_t cols = in.u32();
  if (cols > 3) in.fail(QStringLiteral("%1 has %2 columns (3 expected)").arg(QLatin1StringView(what)).arg(cols));
  if (!in.fits(std::uint64_t{rows} * cols, 8, what)) return;
  Z.resize(rows, cols);
  for (Eigen::Index r = 0; r < Z.rows(); ++r)
    for (Eigen::Index c = 0; c < Z.cols(); ++c) Z(r, c) = in.f64();
}

QString validateMeshPart(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, int m) {
  const auto n = static_cast<int>(V.rows());
  if (V.cols() != 3 || n < 4) return QStringLiteral("the mesh has %1 vertices (at least 4 needed)").arg(n);
  if (F.cols() != 3 || F.rows() < 1) return QStringLiteral("the mesh has no faces");
  if (!V.allFinite()) return QStringLiteral("a vertex position is not finite");
  if (F.minCoeff() < 0 || F.maxCoeff() >= n)
    return QStringLiteral("a face refers to a vertex outside 0..%1").arg(n - 1);
  if (m < 1 || m >= n) return QStringLiteral("m = %1 is not in 1..%2").arg(m).arg(n - 1);
  return {};
}

}  // namespace sc::model::detail
