#pragma once
// The one error type of a user's mistake: main() prints its message as one line on stderr and
// exits with status 2. Everything that parses what a user typed throws it (InputError, a file
// that cannot be used, derives from it).
#include <stdexcept>

namespace suite {

struct UsageError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

}  // namespace suite
