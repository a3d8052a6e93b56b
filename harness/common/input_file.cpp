#include "harness/common/input_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "harness/common/sysfs_file.hpp"

namespace suite {

namespace {

InputText refused(std::string reason) { return {false, "", std::move(reason)}; }

std::string not_regular(mode_t mode) { return std::string("is ") + file_kind(mode) + ", not a regular file"; }

}  // namespace

InputText read_regular_file(const std::string& path, std::uint64_t max_bytes) {
    struct stat st {};
    if (stat(path.c_str(), &st) != 0) return refused(std::string("cannot read it: ") + std::strerror(errno));
    if (!S_ISREG(st.st_mode)) return refused(not_regular(st.st_mode));
    const int fd = open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY);
    if (fd < 0) return refused(std::string("cannot open it: ") + std::strerror(errno));
    struct Closer {
        int fd;
        ~Closer() { close(fd); }
    } closer{fd};
    if (fstat(fd, &st) != 0) return refused(std::string("cannot read it: ") + std::strerror(errno));
    if (!S_ISREG(st.st_mode)) return refused(not_regular(st.st_mode));
    if (static_cast<std::uint64_t>(st.st_size) > max_bytes)
        return refused("larger than " + std::to_string(max_bytes >> 20) + " MiB");
    InputText in{true, "", ""};
    in.text.reserve(static_cast<std::size_t>(st.st_size));
    char buf[1 << 16];
    for (;;) {
        const ssize_t n = read(fd, buf, sizeof buf);
        if (n < 0 && errno == EINTR) continue;
        if (n < 0) return refused(std::string("read error: ") + std::strerror(errno));
        if (n == 0) break;
        in.text.append(buf, static_cast<std::size_t>(n));
        // A file that grows while it is read is bounded all the same.
        if (in.text.size() > max_bytes) return refused("larger than " + std::to_string(max_bytes >> 20) + " MiB");
    }
    return in;
}

}  // namespace suite
