#include "io/files.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace odec {

const char* file_kind(mode_t mode) {
    return S_ISREG(mode)    ? "a regular file"
           : S_ISDIR(mode)  ? "a directory"
           : S_ISFIFO(mode) ? "a named pipe"
           : S_ISCHR(mode)  ? "a character device"
           : S_ISBLK(mode)  ? "a block device"
           : S_ISSOCK(mode) ? "a socket"
                            : "not a plain file";
}

namespace {

// The descriptor blocking again: O_NONBLOCK was for the open only.
bool make_blocking(int fd) {
    const int fl = ::fcntl(fd, F_GETFL);
    return fl >= 0 && ::fcntl(fd, F_SETFL, fl & ~O_NONBLOCK) == 0;
}

} // namespace

int open_regular_for_reading(const std::string& path, unsigned long long& size, std::string& error) {
    // O_NONBLOCK: opening a named pipe must not wait for a writer; it is refused below.
    const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0) {
        error = std::strerror(errno);
        return -1;
    }
    struct stat st;
    if (::fstat(fd, &st) != 0 || (S_ISREG(st.st_mode) && !make_blocking(fd))) {
        error = std::strerror(errno);
        ::close(fd);
        return -1;
    }
    if (!S_ISREG(st.st_mode)) {
        error = std::string("it is ") + file_kind(st.st_mode) + ", not a regular file";
        ::close(fd);
        return -1;
    }
    size = static_cast<unsigned long long>(st.st_size);
    return fd;
}

int open_for_writing(const std::string& path, int flags, std::string& error) {
    // O_NONBLOCK: a named pipe with no reader fails at once (ENXIO) instead of waiting; one
    // with a reader is refused below.
    const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_NONBLOCK | O_CLOEXEC | flags, 0666);
    if (fd < 0) {
        error = errno == ENXIO ? std::string("it is a named pipe, not a regular file") : std::strerror(errno);
        return -1;
    }
    struct stat st;
    if (::fstat(fd, &st) != 0 || !make_blocking(fd)) {
        error = std::strerror(errno);
        ::close(fd);
        return -1;
    }
    if (!S_ISREG(st.st_mode) && !S_ISCHR(st.st_mode)) {
        error = std::string("it is ") + file_kind(st.st_mode) + ", not a regular file";
        ::close(fd);
        return -1;
    }
    return fd;
}

bool read_file_text(const std::string& path, std::string& text, std::string& error, std::size_t max_bytes) {
    text.clear();
    unsigned long long size = 0;
    const int fd = open_regular_for_reading(path, size, error);
    if (fd < 0) return false;
    struct FdCloser {
        int fd;
        ~FdCloser() { ::close(fd); }
    } closer{fd};
    if (size > max_bytes) {
        error = "the file is larger than " + std::to_string(max_bytes >> 20) + " MiB (" + std::to_string(size) +
                " bytes)";
        return false;
    }
    text.resize(static_cast<std::size_t>(size));
    std::size_t got = 0;
    char more[4096];
    for (;;) {
        // Into the space the size promised, then in chunks (a file may grow while it is read).
        char* into = got < text.size() ? &text[got] : more;
        const std::size_t room = got < text.size() ? text.size() - got : sizeof more;
        const ssize_t r = ::read(fd, into, room);
        if (r == 0) break;
        if (r < 0) {
            if (errno == EINTR) continue;
            error = std::strerror(errno);
            text.clear();
            return false;
        }
        const auto n = static_cast<std::size_t>(r);
        if (into == more) {
            if (got + n > max_bytes) {
                error = "the file is larger than " + std::to_string(max_bytes >> 20) + " MiB";
                text.clear();
                return false;
            }
            text.append(more, n);
        }
        got += n;
    }
    text.resize(got);
    return true;
}

std::string read_file_text(const std::string& path, bool& ok) {
    std::string text, error;
    ok = read_file_text(path, text, error);
    return text;
}

bool write_all(int fd, const void* p, std::size_t n) {
    const char* c = static_cast<const char*>(p);
    std::size_t done = 0;
    while (done < n) {
        const ssize_t k = ::write(fd, c + done, n - done);
        if (k < 0) {
            if (errno == EINTR) continue;
            return false;
        }
        if (k == 0) {
            errno = EIO;
            return false;
        }
        done += static_cast<std::size_t>(k);
    }
    return true;
}

} // namespace odec
