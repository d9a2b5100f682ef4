// shapecast-bench-datagram: per-datagram cost of authenticating and encrypting one coefficient datagram of the default
// layout (m = 100, 2 parts: 378 bytes), median over rounds of many datagrams:
//   qt-hmac      a new QMessageAuthenticationCode per datagram (what the codec did before Issue 14), over the
//                378-byte datagram's authenticated bytes
//   openssl-hmac the per-peer DatagramMac (an EVP_MAC context keyed once, re-initialised per datagram): PathOpen
//                and path probes
//   gcm-seal/open AES-128-GCM on the per-peer DatagramCipher (keyed once; per datagram only the nonce), header as
//                AAD: what coefficient datagrams cost since protocol version 3
//   encode/decode the whole codec path (quantise + seal / open + parse + replay window)
// Usage: shapecast-bench-datagram [datagrams per round = 20000] [rounds = 15]

#include "experiments/report/machine_info.h"
#include "session/wire/coefficient_codec.h"
#include "session/wire/datagram_cipher.h"
#include "session/wire/datagram_mac.h"

#include <QtCore/QCryptographicHash>
#include <QtCore/QMessageAuthenticationCode>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <vector>

namespace {

using namespace sc::session;

/// Median over `rounds` of the µs per call of `body` called `count` times (one warm-up round first).
double medianMicros(int count, int rounds, const std::function<void()>& body) {
  std::vector<double> us;
  for (int round = -1; round < rounds; ++round) {
    const auto start = std::chrono::steady_clock::now();
    for (int i = 0; i < count; ++i) body();
    const auto stop = std::chrono::steady_clock::now();
    if (round >= 0) us.push_back(std::chrono::duration<double, std::micro>(stop - start).count() / count);
  }
  std::sort(us.begin(), us.end());
  return us[us.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  const int count = argc > 1 ? std::atoi(argv[1]) : 20000;
  const int rounds = argc > 2 ? std::atoi(argv[2]) : 15;
  if (count <= 0 || rounds <= 0) {
    std::fprintf(stderr, "usage: shapecast-bench-datagram [datagrams per round] [rounds]\n");
    return 2;
  }
  const QByteArray key(kDatagramKeySize, '\x42');
  const Eigen::MatrixXd Z = Eigen::MatrixXd::Random(100, 3);
  CoefficientEncoder encoder(key, 7);
  const std::vector<QByteArray> frame = encoder.encodeFrame(1, Z);
  const QByteArray& datagram = frame.front();
  const QByteArrayView body = QByteArrayView(datagram).first(datagram.size() - kTagSize);

  std::printf("machine       %s\n", qPrintable(sc::report::machineDescription()));
  std::printf("datagram      %lld bytes (m = 100, 2 parts), %d per round, median of %d rounds\n",
              static_cast<long long>(datagram.size()), count, rounds);
  char sink = 0;
  const double qt = medianMicros(count, rounds, [&] {
    QMessageAuthenticationCode mac(QCryptographicHash::Sha256, key);
    mac.addData(body.data(), body.size());
    sink = static_cast<char>(sink ^ mac.result().at(0));
  });
  std::printf("qt-hmac       %.3f us/datagram (new QMessageAuthenticationCode per datagram)\n", qt);
  const DatagramMac mac(key);
  const double openssl = medianMicros(count, rounds, [&] { sink = static_cast<char>(sink ^ mac.tag({body})[0]); });
  std::printf("openssl-hmac  %.3f us/datagram (per-peer EVP_MAC context)\n", openssl);

  const DatagramCipher sealer(key, DatagramDirection::HostToClient), opener(key, DatagramDirection::HostToClient);
  const QByteArrayView header = body.first(kDatagramHeaderSize), payload = body.sliced(kDatagramHeaderSize);
  QByteArray sealed;
  sealed.reserve(kMaxDatagramSize);
  std::uint64_t sequence = 0;
  const double seal = medianMicros(count, rounds, [&] {
    sealed.resize(0);
    sealer.seal(sequence++, header, payload, sealed);
    sink = static_cast<char>(sink ^ sealed.at(0));
  });
  std::printf("gcm-seal      %.3f us/datagram (AES-128-GCM, per-peer EVP_CIPHER_CTX, header as AAD)\n", seal);
  sealed.resize(0);
  sealer.seal(7, header, payload, sealed);
  QByteArray opened;
  int rejected = 0;
  const double open = medianMicros(count, rounds, [&] { rejected += !opener.open(7, header, sealed, opened); });
  std::printf("gcm-open      %.3f us/datagram (decrypt + tag check), %d rejected\n", open, rejected);

  std::uint32_t frameNumber = 2;
  const double encode = medianMicros(
      count, rounds, [&] { sink = static_cast<char>(sink ^ encoder.encodeFrame(frameNumber++, Z).front().at(30)); });
  std::printf("encode        %.3f us/frame of 2 datagrams (quantise + seal)\n", encode);
  // Decoding: a fresh stream per round would be needed for the replay window; decode distinct datagrams instead.
  std::vector<QByteArray> stream;
  CoefficientEncoder streamEncoder(key, 7);
  for (std::uint32_t f = 0; static_cast<int>(stream.size()) < count * (rounds + 1); ++f)
    for (QByteArray& part : streamEncoder.encodeFrame(f, Z)) stream.push_back(std::move(part));
  CoefficientDecoder decoder(key, 7);
  std::size_t next = 0;
  int failures = 0;
  const double decode = medianMicros(count, rounds, [&] {
    DecodedDatagram out;
    failures += decoder.decode(stream[next++], out) != DecodeError::None;
  });
  std::printf("decode        %.3f us/datagram (open + parse + replay window), %d failed\n", decode, failures);
  return sink == 127 ? 1 : 0;  // keeps the results observable
}
