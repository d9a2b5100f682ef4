// Entry point of the socket tests: one QCoreApplication (event loop for QUdpSocket/QTimer) for every test, created
// after GoogleTest has parsed its flags (pattern of tests/app/test_main.cpp, without a GUI).

#include <gtest/gtest.h>

#include <QtCore/QCoreApplication>

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  QCoreApplication app(argc, argv);
  return RUN_ALL_TESTS();
}
