#pragma once
// The one big-endian writer/reader shared by every control message codec (wire_format.h, "control messages").
// ByteReader never reads out of bounds: a read past the end returns a zero value and marks the reader failed
// (sticky), so a decoder reads all its fields and checks ok()/finished() once at the end.

#include <QtCore/QByteArray>
#include <QtCore/QByteArrayView>
#include <QtCore/QtEndian>

#include <bit>
#include <cstdint>

namespace sc::session {

/// Appends fixed-width big-endian fields to a QByteArray it does not own.
class ByteWriter {
 public:
  explicit ByteWriter(QByteArray& out) : m_out(out) {}

  template <typename T>
  void put(T value) {
    char bytes[sizeof(T)];
    qToBigEndian(value, bytes);
    m_out.append(bytes, static_cast<qsizetype>(sizeof(T)));
  }
  void u8(std::uint8_t value) { put(value); }
  void u16(std::uint16_t value) { put(value); }
  void u32(std::uint32_t value) { put(value); }
  void u64(std::uint64_t value) { put(value); }
  void f64(double value) { put(std::bit_cast<std::uint64_t>(value)); }
  void bytes(QByteArrayView bytes) { m_out.append(bytes.data(), bytes.size()); }

 private:
  QByteArray& m_out;
};

/// Reads fixed-width big-endian fields from a view it does not own; bounds-checked, sticky failure.
class ByteReader {
 public:
  explicit ByteReader(QByteArrayView bytes) : m_bytes(bytes) {}

  template <typename T>
  T get() {
    if (!take(static_cast<qsizetype>(sizeof(T)))) return T{};
    return qFromBigEndian<T>(m_bytes.data() + m_pos - static_cast<qsizetype>(sizeof(T)));
  }
  std::uint8_t u8() { return get<std::uint8_t>(); }
  std::uint16_t u16() { return get<std::uint16_t>(); }
  std::uint32_t u32() { return get<std::uint32_t>(); }
  std::uint64_t u64() { return get<std::uint64_t>(); }
  double f64() { return std::bit_cast<double>(get<std::uint64_t>()); }
  /// `count` raw bytes (a copy); empty and failed when fewer remain or count < 0.
  QByteArray bytes(qsizetype count) {
    if (!take(count)) return {};
    return m_bytes.sliced(m_pos - count, count).toByteArray();
  }

  void fail() { m_ok = false; }
  bool ok() const { return m_ok; }
  qsizetype remaining() const { return m_bytes.size() - m_pos; }
  /// True when every read succeeded and the input was consumed exactly.
  bool finished() const { return m_ok && m_pos == m_bytes.size(); }

 private:
  bool take(qsizetype count) {
    if (!m_ok || count < 0 || count > remaining()) {
      m_ok = false;
      return false;
    }
    m_pos += count;
    return true;
  }

  QByteArrayView m_bytes;
  qsizetype m_pos = 0;
  bool m_ok = true;
};

}  // namespace sc::session
