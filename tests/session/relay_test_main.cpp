// main() of the relay suites with a broker: a QCoreApplication for the event loop, and cnats' library state released
// at the end (natsShutdown: nats_Close), after every connection is gone, so that LeakSanitizer sees no cnats threads.
#include "session/net/nats_client.h"

#include <gtest/gtest.h>

#include <QtCore/QCoreApplication>

int main(int argc, char** argv) {
  sc::session::keepOpenSslStateUntilExit();  // before anything uses OpenSSL
  ::testing::InitGoogleTest(&argc, argv);
  int result = 0;
  {
    QCoreApplication app(argc, argv);
    result = RUN_ALL_TESTS();
  }
  sc::session::natsShutdown();
  return result;
}
