#pragma once
// The one reader of a file the user names as an input (a result, a roofline file, a mesh, a
// history run): a regular file, read whole, that never makes the suite wait. A FIFO, socket,
// device or directory is refused before it is opened (a FIFO would block the open until a writer
// came), and what was opened is checked again, so a FIFO swapped in meanwhile is refused too.
// Never throws: the caller turns the reason into its own error (InputError, MeshError, ...).
#include <cstdint>
#include <string>

namespace suite {

struct InputText {
    bool ok = false;
    std::string text;    // when ok: the whole content
    std::string reason;  // when !ok: why, without the path ("is a named pipe (FIFO), not a regular file")
};

// `max_bytes`: a larger file is refused unread (the caller names what it expected).
InputText read_regular_file(const std::string& path, std::uint64_t max_bytes);

}  // namespace suite
