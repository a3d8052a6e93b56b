#pragma once
// Facts about this build, filled in by CMake (cmake/build_info.cpp.in, cmake/git_revision.cmake).
namespace suite::build {
extern const char* const version;
extern const char* const git_revision;
extern const char* const compiler;
extern const char* const flags;
extern const char* const build_type;
// The optional parts this build has and has not, one phrase each: "suite-mpi (Open MPI 4.1),
// suite matrix's SuiteSparse and METIS, the valgrind twin, libpfm4 counters, ..."
extern const char* const parts;
}  // namespace suite::build
