#include "session/wire/control_codec.h"

#include <cmath>

namespace sc::session::detail {

void writeText(ByteWriter& writer, const QString& text, Prefix prefix) {
  const QByteArray utf8 = text.toUtf8();
  if (prefix == Prefix::U8) {
    writer.u8(static_cast<std::uint8_t>(utf8.size()));
  } else {
    writer.u16(static_cast<std::uint16_t>(utf8.size()));
  }
  writer.bytes(utf8);
}

bool readText(ByteReader& reader, QString& text, Prefix prefix, int maxBytes) {
  const int size = prefix == Prefix::U8 ? reader.u8() : reader.u16();
  if (size > maxBytes) return false;
  const QByteArray utf8 = reader.bytes(size);
  text = QString::fromUtf8(utf8);
  return reader.ok() && text.toUtf8() == utf8;  // invalid sequences became U+FFFD and no longer match
}

bool readFinite(ByteReader& reader, double& value) {
  value = reader.f64();
  return std::isfinite(value);
}

}  // namespace sc::session::detail
