#include "session/wire/wire_format.h"

#include <QtCore/QtEndian>

namespace sc::session {
namespace {

template <typename T>
void appendBig(QByteArray& out, T value) {
  char bytes[sizeof(T)];
  qToBigEndian(value, bytes);
  out.append(bytes, static_cast<qsizetype>(sizeof(T)));
}

template <typename T>
T readBig(const char* at) {
  return qFromBigEndian<T>(at);
}

}  // namespace

void encodeDatagramHeader(const DatagramHeader& header, QByteArray& out) {
  appendBig<std::uint16_t>(out, header.magic);
  appendBig<std::uint8_t>(out, header.version);
  appendBig<std::uint8_t>(out, static_cast<std::uint8_t>(header.type));
  appendBig<std::uint16_t>(out, header.peerId);
  appendBig<std::uint16_t>(out, header.sequence);
  appendBig<std::uint32_t>(out, header.frame);
  appendBig<std::uint8_t>(out, header.partIndex);
  appendBig<std::uint8_t>(out, header.partCount);
  appendBig<std::uint16_t>(out, header.rowCount);
  appendBig<std::uint8_t>(out, header.protectedRows);
  appendBig<std::uint8_t>(out, header.bandRows);
  appendBig<std::uint32_t>(out, header.timestamp);
}

std::optional<DatagramHeader> decodeDatagramHeader(QByteArrayView bytes) {
  if (bytes.size() < kDatagramHeaderSize) return std::nullopt;
  const char* at = bytes.data();
  DatagramHeader header;
  header.magic = readBig<std::uint16_t>(at + 0);
  header.version = readBig<std::uint8_t>(at + 2);
  header.type = static_cast<MessageType>(readBig<std::uint8_t>(at + 3));
  header.peerId = readBig<std::uint16_t>(at + 4);
  header.sequence = readBig<std::uint16_t>(at + 6);
  header.frame = readBig<std::uint32_t>(at + 8);
  header.partIndex = readBig<std::uint8_t>(at + 12);
  header.partCount = readBig<std::uint8_t>(at + 13);
  header.rowCount = readBig<std::uint16_t>(at + 14);
  header.protectedRows = readBig<std::uint8_t>(at + 16);
  header.bandRows = readBig<std::uint8_t>(at + 17);
  header.timestamp = readBig<std::uint32_t>(at + 18);
  return header;
}

int bandCount(const DatagramHeader& header) {
  if (header.bandRows == 0) return 0;
  return (header.rowCount + header.bandRows - 1) / header.bandRows;
}

int interleavedRowCount(const DatagramHeader& header) {
  const int unprotected = header.rowCount - header.protectedRows;
  if (unprotected <= header.partIndex || header.partCount == 0) return 0;
  return (unprotected - header.partIndex + header.partCount - 1) / header.partCount;
}

int expectedDatagramSize(const DatagramHeader& header) {
  const int rows = header.protectedRows + interleavedRowCount(header);
  return kDatagramHeaderSize + bandCount(header) + rows * kRowSize + kTagSize;
}

bool headerRangesValid(const DatagramHeader& header) {
  const auto type = static_cast<std::uint8_t>(header.type);
  const bool typeOk = type == static_cast<std::uint8_t>(MessageType::CoefficientFrame);
  return typeOk && header.partCount >= 1 && header.partCount <= kMaxParts && header.partIndex < header.partCount &&
         header.rowCount >= 1 && header.rowCount <= kMaxRows && header.protectedRows <= header.rowCount &&
         header.bandRows >= 1;
}

void appendInt16(QByteArray& out, std::int16_t value) { appendBig<std::int16_t>(out, value); }

std::int16_t readInt16(const char* at) { return readBig<std::int16_t>(at); }

}  // namespace sc::session
