# Sanitiser and fuzzing builds (docs/fuzzing.md). Both apply to every target of the build folder, so that
# libraries and tests share one instrumentation (ASan needs every allocation site it checks to be instrumented).
#
#   SHAPECAST_SANITIZE  AddressSanitizer (+ LeakSanitizer) and UndefinedBehaviorSanitizer, GCC or Clang. A UB report
#                       aborts the test (-fno-sanitize-recover) so that ctest sees it as a failure. scripts/test.sh
#                       builds it into build-asan/ and runs the whole suite (LSan suppressions: cmake/lsan.supp).
#   SHAPECAST_FUZZ      The same sanitisers plus libFuzzer's coverage instrumentation (Clang only); fuzz/ then
#                       builds libFuzzer executables instead of replay tests. scripts/fuzz.sh builds it into build-fuzz/.
if(SHAPECAST_SANITIZE OR SHAPECAST_FUZZ)
  add_compile_options(-fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined)
  add_link_options(-fsanitize=address,undefined)
endif()

if(SHAPECAST_FUZZ)
  if(NOT CMAKE_CXX_COMPILER_ID MATCHES "Clang")
    message(FATAL_ERROR "SHAPECAST_FUZZ needs Clang (libFuzzer): configure with -DCMAKE_CXX_COMPILER=clang++")
  endif()
  # Coverage feedback for every library; the fuzz executables add -fsanitize=fuzzer (libFuzzer's main) themselves.
  add_compile_options(-fsanitize=fuzzer-no-link)
endif()
