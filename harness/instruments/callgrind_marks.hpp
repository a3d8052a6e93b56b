#pragma once
// Marks for valgrind's callgrind around the kernel's calls, so that `suite deterministic`
// (valgrind --collect-atstart=no) counts the kernel and nothing else: no setup, no warm-up, no
// clock reads. Outside valgrind each mark is a handful of no-op instructions. Compiled in only
// where <valgrind/callgrind.h> exists (Debian: valgrind); `available` says whether it was.
#if __has_include(<valgrind/callgrind.h>)
#include <valgrind/callgrind.h>
#define SUITE_CALLGRIND_MARKS 1
#endif

namespace suite::callgrind {

#ifdef SUITE_CALLGRIND_MARKS
constexpr bool available = true;
// Starts or stops counting (callgrind's collection state flips).
inline void toggle_collect() { CALLGRIND_TOGGLE_COLLECT; }
// Writes what was counted since the last dump to its own file, labelled, and starts afresh.
inline void dump(const char* label) { CALLGRIND_DUMP_STATS_AT(label); }
inline bool running_on_valgrind() { return RUNNING_ON_VALGRIND != 0; }
#else
constexpr bool available = false;
inline void toggle_collect() {}
inline void dump(const char*) {}
inline bool running_on_valgrind() { return false; }
#endif

}  // namespace suite::callgrind
