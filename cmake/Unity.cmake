# shapecast_unity_directory(): compiles the targets defined after it in the calling directory (and below) as unity
# (jumbo) translation units of up to 16 files, when SHAPECAST_UNITY is on (the default).
#
# Why: most of a test or app file's compile time is parsing the same Qt, Eigen and GoogleTest headers (measured for
# tests/session/security_channel_test.cpp: 9.0 s to compile, 9.5 s for -fsyntax-only alone), and CI builds
# everything twice (normal and sanitiser jobs). Unity files cut the test suites' compile time roughly in half.
# GCC's -Wsubobject-linkage assumes that a file including a .cpp is a header, which a unity file is not, so it is
# off in these directories. SHAPECAST_UNITY=OFF builds file by file (e.g. to check that every file includes what it
# uses, or that no two files of a target define the same name in an anonymous namespace).
option(SHAPECAST_UNITY "Compile the tests and the app as unity (jumbo) translation units (faster builds)" ON)

macro(shapecast_unity_directory)
  set(CMAKE_UNITY_BUILD ${SHAPECAST_UNITY})
  set(CMAKE_UNITY_BUILD_BATCH_SIZE 16)
  if(SHAPECAST_UNITY AND CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
    add_compile_options(-Wno-subobject-linkage)
  endif()
endmacro()
