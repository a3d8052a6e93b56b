# Run at every build (not only at configure time) so the recorded revision follows commits.
# Rewrites OUT only when the revision changed, so an unchanged tree does not relink.
execute_process(COMMAND git describe --always --dirty --abbrev=12
                WORKING_DIRECTORY "${SRC}" OUTPUT_VARIABLE rev OUTPUT_STRIP_TRAILING_WHITESPACE
                RESULT_VARIABLE rc ERROR_QUIET)
if(NOT rc EQUAL 0 OR rev STREQUAL "")
  set(rev "unknown")
endif()
set(content "// Generated at build time by cmake/git_revision.cmake.\n#include \"harness/results/build_info.hpp\"\nconst char* const suite::build::git_revision = \"${rev}\";\n")
if(EXISTS "${OUT}")
  file(READ "${OUT}" old)
endif()
if(NOT "${old}" STREQUAL "${content}")
  file(WRITE "${OUT}" "${content}")
endif()
