// Fuzz target "session_file": decodeSessionFile(), the saved-session (.shapecast) reader (model/session_file.h),
// version 2 and the legacy version 1 (model/session_file_v1.h).
//
// Input: one mode byte, then bytes. Mode bit 0 clear: the bytes are a whole file, decoded as they are. Bit 0 set:
// the bytes are a payload, sealed first with the header (magic, version 2 — or 1 when bit 1 is set —, its length)
// and a valid SHA-256, so the fuzzer gets past the checksum to the payload parsers (counts, id lists, edit steps
// and their author names and ΔZ; version 1's "same as previous" lists and poses).
// Invariants checked: a decoded file passes validateSessionFile(); it holds at most kMaxSavedEditSteps steps and
// its constraint lists at most #V ids; encoding it (always version 2) and decoding again gives the same file
// (but for droppedLegacyDrags, which version 2 does not store).

#include "fuzz_support.h"
#include "model/session_file.h"

#include <QByteArray>
#include <QCryptographicHash>
#include <QtEndian>

#include <cstring>
#include <variant>

namespace {

/// `payload` with the header of `version` and a valid checksum around it.
QByteArray sealed(const QByteArray& payload, std::uint32_t version) {
  QByteArray out(sc::model::kSessionFileMagic, sizeof(sc::model::kSessionFileMagic));
  const std::uint32_t le = qToLittleEndian(version);
  const std::uint64_t length = qToLittleEndian(static_cast<std::uint64_t>(payload.size()));
  out.append(reinterpret_cast<const char*>(&le), sizeof le);
  out.append(reinterpret_cast<const char*>(&length), sizeof length);
  out.append(payload);
  out.append(QCryptographicHash::hash(out, QCryptographicHash::Sha256));
  return out;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const sc::fuzz::Input input = sc::fuzz::splitMode(data, size);
  QByteArray bytes(reinterpret_cast<const char*>(input.rest.data()), static_cast<qsizetype>(input.rest.size()));
  if ((input.mode & 1) != 0) bytes = sealed(bytes, (input.mode & 2) != 0 ? 1 : sc::model::kSessionFileVersion);
  const sc::model::SessionFileResult result = sc::model::decodeSessionFile(bytes);
  const auto* file = std::get_if<sc::model::SessionFile>(&result);
  if (file == nullptr) {
    sc::fuzz::check(!std::get<sc::model::SessionFileError>(result).message.isEmpty(), "an error says why");
    return 0;
  }
  sc::fuzz::check(sc::model::validateSessionFile(*file).isEmpty(), "a decoded file is valid");
  sc::fuzz::check(file->steps.size() <= static_cast<std::size_t>(sc::model::kMaxSavedEditSteps), "steps bounded");
  const qint64 ids =
      file->current ? static_cast<qint64>(file->current->handle.size() + file->current->anchors.size()) : 0;
  sc::fuzz::check(ids <= file->V.rows(), "the id lists (disjoint) hold at most #V ids");
  const sc::model::SessionFileResult again = sc::model::decodeSessionFile(sc::model::encodeSessionFile(*file));
  const auto* reread = std::get_if<sc::model::SessionFile>(&again);
  sc::fuzz::check(reread != nullptr && reread->droppedLegacyDrags == 0, "re-encoded as version 2");
  sc::model::SessionFile expected = *file;
  expected.droppedLegacyDrags = 0;
  sc::fuzz::check(sc::model::sameSessionFile(*reread, expected), "encode + decode round trip");
  return 0;
}
