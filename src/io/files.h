// Opening the files a user names, the same way for every command that reads or writes one.
//
// Whatever a user types as a file name must neither hang odec nor exhaust its memory: a named
// pipe with no writer would block an ordinary open() for ever, /dev/zero never ends, a
// directory cannot be read as text. Readers therefore open without blocking, look at what they
// opened, and refuse anything but a regular file (and text files above a size) before reading
// a byte. Writers refuse what would block or cannot hold a file (a named pipe, a directory, a
// socket) and report every failed write with the system's reason.
#pragma once

#include <sys/types.h>

#include <cstddef>
#include <string>

namespace odec {

// Largest file `call`, `table read` and FISH read() take: a script or a table is text a person
// wrote.
constexpr std::size_t kMaxTextFileBytes = std::size_t{64} << 20;

// "a directory", "a named pipe", "a character device", ...: what a file that is not a regular
// one is, for messages.
const char* file_kind(mode_t mode);

// Open `path` for reading, without waiting on a named pipe. Returns the descriptor (blocking
// again, close-on-exec) with its size in `size`, or -1 with `error` saying why (the system's
// reason, or "it is a named pipe, not a regular file").
int open_regular_for_reading(const std::string& path, unsigned long long& size, std::string& error);

// Open `path` for writing (`flags`: O_TRUNC or O_APPEND, with O_CREAT implied), without waiting
// on a named pipe. Regular files and character devices (/dev/null, a terminal) are taken;
// anything else is refused. Returns the descriptor (blocking again, close-on-exec), or -1 with
// `error` saying why.
int open_for_writing(const std::string& path, int flags, std::string& error);

// Read a whole text file. Refuses (false, with `error` saying why, e.g. "it is a directory, not
// a regular file") anything but a regular file, and files larger than max_bytes, without reading
// them; never waits on a named pipe.
bool read_file_text(const std::string& path, std::string& text, std::string& error,
                    std::size_t max_bytes = kMaxTextFileBytes);
// The same, for callers that only need to know whether it worked.
std::string read_file_text(const std::string& path, bool& ok);

// Write all of [p, p + n) to fd, through short writes and interrupted calls. False with errno
// set when a write failed.
bool write_all(int fd, const void* p, std::size_t n);

} // namespace odec
