#pragma once
// Internal to the session file (session_file.h), shared by its current version (session_file.cpp) and the legacy
// version 1 (session_file_v1.cpp): the little-endian byte writer and the bounds-checked reader the payloads go
// through, the envelope around a payload (magic, version, length, SHA-256), and the payload's parts that both
// versions share (mesh, m, mode; coefficients). Not part of the model's public API: app code uses session_file.h.

#include "spectral/spectral_deformer.h"

#include <Eigen/Core>
#include <QByteArray>
#include <QByteArrayView>
#include <QString>

#include <cstdint>

namespace sc::model::detail {

inline constexpr qsizetype kSessionHeaderBytes = 8 + 4 + 8;  // magic, version, payload length
inline constexpr qsizetype kSessionChecksumBytes = 32;       // SHA-256

/// Appends little-endian integers and IEEE-754 doubles. Cost: amortised O(1) per value.
class ByteWriter {
 public:
  void u8(std::uint8_t v);
  void u32(std::uint32_t v);
  void u64(std::uint64_t v);
  void f64(double v);
  void raw(QByteArrayView bytes);
  [[nodiscard]] QByteArray& bytes() { return m_bytes; }

 private:
  QByteArray m_bytes;
};

/// Bounds-checked little-endian reader; the first failure sticks (error()) and every later read returns zeros, so
/// a parser may read on and check ok() once. Never reads outside `data`.
class ByteReader {
 public:
  explicit ByteReader(QByteArrayView data) : m_data(data) {}

  [[nodiscard]] bool ok() const { return m_error.isEmpty(); }
  [[nodiscard]] const QString& error() const { return m_error; }
  [[nodiscard]] qsizetype left() const { return m_data.size() - m_at; }
  /// Records `why` unless a failure is already recorded.
  void fail(const QString& why);
  /// Whether `count` items of at least `size` bytes (> 0) can still be read; fails otherwise, naming `what`. The
  /// guard before every allocation sized by a count read from the data.
  bool fits(std::uint64_t count, std::uint64_t size, const char* what);

  std::uint8_t u8();
  std::uint32_t u32();
  std::uint64_t u64();
  double f64();
  /// The next `count` bytes (empty and failed when fewer are left); a view into the data, nothing copied.
  QByteArrayView raw(qsizetype count);

 private:
  bool need(qsizetype count);

  QByteArrayView m_data;
  qsizetype m_at = 0;
  QString m_error;
};

/// SHA-256 of `bytes` through OpenSSL (EVP_Digest); empty only if OpenSSL fails.
[[nodiscard]] QByteArray sha256(QByteArrayView bytes);

/// The whole file: magic | u32 version | u64 payload length | payload | SHA-256 of everything before it.
[[nodiscard]] QByteArray sealSessionPayload(std::uint32_t version, const QByteArray& payload);

/// The payload's start in both versions: u32 #V, u32 #F, #V·3 f64 positions, #F·3 u32 indices, u32 m, u8 mode.
void writeMeshPart(ByteWriter& out, const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, int m,
                   spectral::DeformationMode mode);
/// Reads writeMeshPart()'s bytes; counts are checked against the data left before allocating, an index ≥ #V
/// becomes −1 (validation names it), an unknown mode fails. Returns #V as read (the bound of every id list).
std::uint32_t readMeshPart(ByteReader& in, Eigen::MatrixXd& V, Eigen::MatrixXi& F, int& m,
                           spectral::DeformationMode& mode);

/// u32 rows, u32 cols, rows·cols f64 (row-major).
void writeMatrix(ByteWriter& out, const Eigen::MatrixXd& Z);
/// Reads writeMatrix()'s bytes, refusing more than 3 columns and sizes larger than the data left.
void readMatrix(ByteReader& in, Eigen::MatrixXd& Z, const char* what);

/// Empty when V (#V ≥ 4 by 3, finite), F (≥ 1 face, indices in range) and 1 ≤ m < #V are usable, else the problem.
[[nodiscard]] QString validateMeshPart(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, int m);

}  // namespace sc::model::detail
