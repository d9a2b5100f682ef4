# shapecast_set_warnings(target): the project's warning set, errors when SHAPECAST_WERROR is on.
#
# Two GCC 12 warnings are off because they fire only inside Eigen's inlined (system-header) code at -O3:
# -Wmaybe-uninitialized on AVX-512 intrinsics and -Wnull-dereference in SparseCompressedBase (both false
# positives: the values are written before use and the pointers are checked by Eigen).
function(shapecast_set_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wshadow -Wnon-virtual-dtor
                                           -Wold-style-cast -Wcast-align -Woverloaded-virtual
                                           -Wimplicit-fallthrough $<$<CXX_COMPILER_ID:GNU>:-Wno-maybe-uninitialized>)
  if(SHAPECAST_WERROR)
    target_compile_options(${target} PRIVATE -Werror)
  endif()
  if(SHAPECAST_NATIVE)
    target_compile_options(${target} PRIVATE -march=native)
  endif()
endfunction()
