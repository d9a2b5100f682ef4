// Fuzz target "session_file": decodeSessionFile(), the saved-session (.shapecast) reader (model/session_file.h).
//
// Input: one mode byte, then bytes. Mode bit 0 clear: the bytes are a whole file, decoded as they are. Bit 0 set:
// the bytes are a payload, sealed first with the header (magic, version 1, its length) and a valid SHA-256, so the
// fuzzer gets past the checksum to the payload parser (counts, id lists, "same as previous" lists, poses, Z).
// Invariants checked: a decoded file passes validateSessionFile(); its constraint lists hold at most
// kMaxSessionFileIds ids in all (the expansion bound); encoding it and decoding again gives the same file.

#include "fuzz_support.h"
#include "model/session_file.h"

#include <QByteArray>
#include <QCryptographicHash>
#include <QtEndian>

#include <cstring>
#include <variant>

namespace {

/// `payload` with the header and a valid checksum around it.
QByteArray sealed(const QByteArray& payload) {
  QByteArray out(sc::model::kSessionFileMagic, sizeof(sc::model::kSessionFileMagic));
  const std::uint32_t version = qToLittleEndian(sc::model::kSessionFileVersion);
  const std::uint64_t length = qToLittleEndian(static_cast<std::uint64_t>(payload.size()));
  out.append(reinterpret_cast<const char*>(&version), sizeof version);
  out.append(reinterpret_cast<const char*>(&length), sizeof length);
  out.append(payload);
  out.append(QCryptographicHash::hash(out, QCryptographicHash::Sha256));
  return out;
}

/// Ids held by every list of `file` (as expanded in memory).
qint64 idsHeld(const sc::model::SessionFile& file) {
  const auto ids = [](const sc::model::SavedDeformation& d) {
    return static_cast<qint64>(d.handle.size() + d.anchors.size());
  };
  qint64 total = file.current ? ids(*file.current) : 0;
  for (const sc::model::SavedDrag& drag : file.history) total += ids(drag.before) + ids(drag.after);
  return total;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const sc::fuzz::Input input = sc::fuzz::splitMode(data, size);
  QByteArray bytes(reinterpret_cast<const char*>(input.rest.data()), static_cast<qsizetype>(input.rest.size()));
  if ((input.mode & 1) != 0) bytes = sealed(bytes);
  const sc::model::SessionFileResult result = sc::model::decodeSessionFile(bytes);
  const auto* file = std::get_if<sc::model::SessionFile>(&result);
  if (file == nullptr) {
    sc::fuzz::check(!std::get<sc::model::SessionFileError>(result).message.isEmpty(), "an error says why");
    return 0;
  }
  sc::fuzz::check(sc::model::validateSessionFile(*file).isEmpty(), "a decoded file is valid");
  sc::fuzz::check(idsHeld(*file) <= sc::model::kMaxSessionFileIds, "the id lists expand within the bound");
  const sc::model::SessionFileResult again = sc::model::decodeSessionFile(sc::model::encodeSessionFile(*file));
  const auto* reread = std::get_if<sc::model::SessionFile>(&again);
  sc::fuzz::check(reread != nullptr && sc::model::sameSessionFile(*reread, *file), "encode + decode round trip");
  return 0;
}
