#pragma once
// Facts about this build, filled in by CMake (cmake/build_info.cpp.in, cmake/git_revision.cmake).
namespace suite::build {
extern const char* const version;
extern const char* const git_revision;
extern const char* const compiler;
extern const char* const flags;
extern const char* const build_type;
}  // namespace suite::build
