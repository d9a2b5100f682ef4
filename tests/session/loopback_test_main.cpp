// Entry point of session_loopback_tests: one QCoreApplication (the sockets need its event loop) for every test,
// created after GoogleTest has parsed its flags.

#include <gtest/gtest.h>

#include <QtCore/QCoreApplication>

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  QCoreApplication app(argc, argv);
  return RUN_ALL_TESTS();
}
