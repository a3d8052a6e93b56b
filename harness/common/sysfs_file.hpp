#pragma once
// The one way the suite reads a kernel attribute file (sysfs, /proc/sys): as such a file
// answers, a regular file of at most 4 KiB whose content is there at once. Never blocks and
// never reads more: a FIFO, a device, a directory, a read that would wait or a file larger than
// the bound is refused with the reason, and the caller treats the thing it wanted as unavailable.
#include <sys/types.h>

#include <cstddef>
#include <string>

namespace suite {

// At most this many bytes: a sysfs attribute holds at most one page.
inline constexpr std::size_t max_attribute_bytes = 4096;

struct AttributeText {
    bool ok = false;
    std::string text;    // when ok: the first line, without its newline
    int error = 0;       // the errno of a failed open or read (EACCES, ENOENT, ...); 0 when the file
                         // answered but not as an attribute does
    std::string reason;  // when !ok: why, naming the path
};

AttributeText read_attribute(const std::string& path);

// What a file that is not a regular one is, for messages: "a named pipe (FIFO)", "a symlink",
// "a character device", ... (the output writer uses it too).
const char* file_kind(mode_t mode);

}  // namespace suite
