# shapecast_set_warnings(target): the project's warning set, errors when SHAPECAST_WERROR is on.
function(shapecast_set_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wshadow -Wnon-virtual-dtor
                                           -Wold-style-cast -Wcast-align -Woverloaded-virtual
                                           -Wnull-dereference -Wimplicit-fallthrough)
  if(SHAPECAST_WERROR)
    target_compile_options(${target} PRIVATE -Werror)
  endif()
  if(SHAPECAST_NATIVE)
    target_compile_options(${target} PRIVATE -march=native)
  endif()
endfunction()
