# groundsim_layer(<target> <layer>): gives a layer library an include root of
# its own, <build>/include/<layer>/, holding only <layer>/ (a link to the
# layer's source folder). A target sees a layer's headers only by linking it,
# so `#include "session/session.hpp"` in a physics source does not compile:
# the layering of docs/architecture.md is enforced by the build
# (tests/layers checks that it is).
function(groundsim_layer target layer)
  set(root ${CMAKE_BINARY_DIR}/include/${layer})
  file(MAKE_DIRECTORY ${root})
  if(NOT EXISTS ${root}/${layer})
    file(CREATE_LINK ${CMAKE_CURRENT_SOURCE_DIR} ${root}/${layer} SYMBOLIC)
  endif()
  target_include_directories(${target} PUBLIC ${root})
endfunction()
