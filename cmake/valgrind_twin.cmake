# suite-x86-64-v3: the same program built for x86-64-v3, for `suite deterministic`, which runs
# the kernels under valgrind's callgrind; valgrind 3.19 cannot decode AVX-512, which
# -march=native emits on AVX-512 machines. Built when the main build targets a specific CPU,
# the machine is x86-64, and <valgrind/callgrind.h> is there (Debian: valgrind).
include(CheckIncludeFileCXX)
check_include_file_cxx(valgrind/callgrind.h SUITE_HAVE_CALLGRIND_H)
set(_generic_arch "x86-64;x86-64-v2;x86-64-v3")
if(SUITE_HAVE_CALLGRIND_H AND CMAKE_SYSTEM_PROCESSOR MATCHES "^(x86_64|AMD64)$" AND SUITE_ARCH AND NOT SUITE_ARCH IN_LIST _generic_arch)
  set(_twin_default ON)
else()
  set(_twin_default OFF)
endif()
option(SUITE_VALGRIND_TWIN "also build suite-x86-64-v3 for the deterministic (valgrind) mode" ${_twin_default})

if(SUITE_VALGRIND_TWIN)
  # Its own build_info, so that its results say which flags really built them.
  set(_main_flags "${SUITE_EFFECTIVE_FLAGS}")
  set(SUITE_EFFECTIVE_FLAGS "${CMAKE_CXX_FLAGS} ${CMAKE_CXX_FLAGS_${_bt}} -march=x86-64-v3 ${OpenMP_CXX_FLAGS}")
  string(STRIP "${SUITE_EFFECTIVE_FLAGS}" SUITE_EFFECTIVE_FLAGS)
  configure_file(cmake/build_info.cpp.in ${CMAKE_BINARY_DIR}/generated/build_info_x86-64-v3.cpp @ONLY)
  set(SUITE_EFFECTIVE_FLAGS "${_main_flags}")
  add_executable(suite-x86-64-v3 app/suite/main.cpp ${SUITE_APP} ${SUITE_HARNESS} ${SUITE_STREAM} ${SUITE_KERNELS} ${SUITE_RAPL}
                 ${CMAKE_BINARY_DIR}/generated/build_info_x86-64-v3.cpp ${CMAKE_BINARY_DIR}/generated/git_revision.cpp
                 ${CMAKE_BINARY_DIR}/generated/build_parts.cpp)
  add_dependencies(suite-x86-64-v3 git_revision)
  target_include_directories(suite-x86-64-v3 PRIVATE ${CMAKE_SOURCE_DIR})
  # The warnings of every other target (suite_usage: -Wall -Wextra, -Werror where asked).
  target_compile_options(suite-x86-64-v3 PRIVATE -march=x86-64-v3 $<TARGET_PROPERTY:suite_usage,INTERFACE_COMPILE_OPTIONS>)
  # The same libraries and definitions as suite_core and suite_front (keep in step with
  # CMakeLists.txt); one -O level for all of it, as it only counts instructions.
  target_link_libraries(suite-x86-64-v3 PRIVATE OpenMP::OpenMP_CXX CLI11::CLI11 nlohmann_json::nlohmann_json PkgConfig::HWLOC suite::numa suite::pfm
                        Boost::headers SQLite::SQLite3 suite_sparse)
  target_compile_definitions(suite-x86-64-v3 PRIVATE $<TARGET_PROPERTY:suite_core,COMPILE_DEFINITIONS>
                             $<TARGET_PROPERTY:suite_front,COMPILE_DEFINITIONS>)
  # The harness's and app/suite's files compile one unit a folder here too (their UNITY_GROUP, CMakeLists.txt).
  set_target_properties(suite-x86-64-v3 PROPERTIES UNITY_BUILD ON UNITY_BUILD_MODE GROUP)
endif()
