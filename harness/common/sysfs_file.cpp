#include "harness/common/sysfs_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace suite {

namespace {

AttributeText failed(const std::string& path, int err) {
    AttributeText a;
    a.error = err;
    a.reason = "cannot read " + path + ": " + std::strerror(err);
    return a;
}

AttributeText refused(const std::string& path, const std::string& why) {
    AttributeText a;
    a.reason = path + " " + why + ", which a sysfs attribute never is; not read";
    return a;
}

}  // namespace

const char* file_kind(mode_t mode) {
    if (S_ISFIFO(mode)) return "a named pipe (FIFO)";
    if (S_ISLNK(mode)) return "a symlink";
    if (S_ISCHR(mode)) return "a character device";
    if (S_ISBLK(mode)) return "a block device";
    if (S_ISDIR(mode)) return "a directory";
    if (S_ISSOCK(mode)) return "a socket";
    if (S_ISREG(mode)) return "a regular file";
    return "not a regular file";
}

AttributeText read_attribute(const std::string& path) {
    // stat() first, so that a FIFO or a device is never even opened; then open without blocking
    // (a FIFO swapped in meanwhile opens at once) and check again what was opened.
    struct stat st {};
    if (stat(path.c_str(), &st) != 0) return failed(path, errno);
    if (!S_ISREG(st.st_mode)) return refused(path, std::string("is ") + file_kind(st.st_mode));
    const int fd = open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY);
    if (fd < 0) return failed(path, errno);
    if (fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
        close(fd);
        return refused(path, std::string("is ") + file_kind(st.st_mode));
    }
    // One byte more than the bound tells a larger file from one of exactly the bound.
    char buf[max_attribute_bytes + 1];
    std::size_t got = 0;
    AttributeText a;
    while (got < sizeof buf) {
        const ssize_t n = read(fd, buf + got, sizeof buf - got);
        if (n > 0) {
            got += static_cast<std::size_t>(n);
            continue;
        }
        if (n == 0) break;
        if (errno == EINTR) continue;
        const int err = errno;
        close(fd);
        if (err == EAGAIN || err == EWOULDBLOCK) return refused(path, "would block on read");
        return failed(path, err);
    }
    close(fd);
    if (got > max_attribute_bytes)
        return refused(path, "holds more than " + std::to_string(max_attribute_bytes) + " bytes");
    a.ok = true;
    a.text.assign(buf, got);
    if (auto nl = a.text.find('\n'); nl != std::string::npos) a.text.resize(nl);
    return a;
}

}  // namespace suite
