// Output and files, as the classic dialect has them: out(s) prints a line; open(name, mode,
// type) opens one file (mode 0 read, 1 write; type 1 text, 0 FISH values written as text too),
// write(array, n) writes the first n elements one per line, read(array, n) reads n lines into
// strings, close closes it. Each returns 0 on success and an error code otherwise, except that
// a misuse (no file open, a bad array) stops the function with a message. A file that cannot be
// opened or written is also said on the error stream, so that a full disk is never silent.
//
// open() takes what `call` and `table read` take: reading, a regular file of at most 64 MiB;
// writing, a regular file or a character device (/dev/null); never a named pipe, which would
// wait for ever for its other end.
#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <ostream>

#include "fish/intrinsics.h"
#include "fish/runtime.h"
#include "io/files.h"

namespace odec::fish {

namespace {

using A = const Value*;
using L = const SourceLoc&;

Value f_out(Runtime& rt, A a, int, L) {
    rt.host.out() << to_text(a[0]) << "\n";
    rt.host.out().flush();
    return Value::integer(0);
}

bool safe_relative(const std::string& p) {
    if (p.empty() || p[0] == '/') return false;
    size_t start = 0;
    while (start <= p.size()) {
        const size_t slash = p.find('/', start);
        const std::string part = p.substr(start, slash == std::string::npos ? std::string::npos : slash - start);
        if (part == "..") return false;
        if (slash == std::string::npos) break;
        start = slash + 1;
    }
    return true;
}

// A file operation counts against a session's bound on FISH work (Runtime::budget) as this many
// loop iterations: opening makes, truncates or checks a file, and every write is flushed to
// it, each a system call that costs far more than an iteration, so that a loop of them ends
// within a bounded session's time as a loop of commands does (Interpreter::kCommandFishSteps).
constexpr long long kOpenFishSteps = 50;
constexpr long long kFileFishSteps = 10;

Value f_open(Runtime& rt, A a, int n, L loc) {
    rt.spend(kOpenFishSteps, loc);
    const std::string name = str_arg(a, 0, "open", loc);
    const long long mode = n > 1 ? int_arg(a, 1, "open", loc) : 0;
    if (mode != 0 && mode != 1) fish_fail(loc, "'open' mode is 0 (read) or 1 (write), not " + std::to_string(mode));
    if (rt.host.confine_files() && !safe_relative(name)) {
        fish_fail(loc, "'open' takes only a relative file name without '..' in this session");
    }
    if (rt.file) {
        std::fclose(rt.file);
        rt.file = nullptr;
    }
    std::string why;
    int fd = -1;
    if (mode == 1) {
        fd = open_for_writing(name, O_TRUNC, why);
    } else {
        unsigned long long size = 0;
        fd = open_regular_for_reading(name, size, why);
        if (fd >= 0 && size > kMaxTextFileBytes) {
            ::close(fd);
            fd = -1;
            why = "the file is larger than " + std::to_string(kMaxTextFileBytes >> 20) + " MiB (" +
                  std::to_string(size) + " bytes)";
        }
    }
    if (fd >= 0) {
        rt.file = ::fdopen(fd, mode == 1 ? "w" : "r");
        if (!rt.file) {
            why = std::strerror(errno);
            ::close(fd);
        }
    }
    if (!rt.file) {
        rt.host.err() << "warning: FISH open('" << name << "'): " << why << "\n";
        return Value::integer(1);
    }
    rt.file_writing = mode == 1;
    rt.file_name = name;
    return Value::integer(0);
}

// Say that the open file could not be written (a full disk): the function gives 1.
Value write_failed(Runtime& rt, int error_number) {
    std::clearerr(rt.file);
    rt.host.err() << "warning: FISH write to '" << rt.file_name << "': " << std::strerror(error_number)
                  << "; what was written may be incomplete\n";
    return Value::integer(1);
}

Array& array_arg(A a, const char* fn, L loc) {
    if (a[0].type != Type::Array || !a[0].a) fish_fail(loc, std::string("'") + fn + "' needs an array as its first argument");
    return *a[0].a;
}

long long count_arg(A a, int n, const Array& arr, const char* fn, L loc) {
    const long long k = n > 1 ? int_arg(a, 1, fn, loc) : static_cast<long long>(arr.items.size());
    if (k < 0 || k > static_cast<long long>(arr.items.size())) {
        fish_fail(loc, std::string("'") + fn + "' of " + std::to_string(k) + " elements from an array of " +
                           std::to_string(arr.items.size()));
    }
    return k;
}

Value f_write(Runtime& rt, A a, int n, L loc) {
    rt.spend(kFileFishSteps, loc);
    Array& arr = array_arg(a, "write", loc);
    const long long k = count_arg(a, n, arr, "write", loc);
    if (!rt.file || !rt.file_writing) fish_fail(loc, "'write' with no file open for writing: open(name, 1, 1) first");
    for (long long i = 0; i < k; ++i) {
        const std::string s = to_text(arr.items[static_cast<size_t>(i)]) + "\n";
        if (std::fwrite(s.data(), 1, s.size(), rt.file) != s.size()) return write_failed(rt, errno);
    }
    // Written through to the file now, so that a full disk shows here and not at close.
    if (std::fflush(rt.file) != 0) return write_failed(rt, errno);
    return Value::integer(0);
}

Value f_read(Runtime& rt, A a, int n, L loc) {
    rt.spend(kFileFishSteps, loc);
    Array& arr = array_arg(a, "read", loc);
    const long long k = count_arg(a, n, arr, "read", loc);
    if (!rt.file || rt.file_writing) fish_fail(loc, "'read' with no file open for reading: open(name, 0, 1) first");
    for (long long i = 0; i < k; ++i) {
        std::string line;
        int c;
        bool any = false;
        while ((c = std::fgetc(rt.file)) != EOF) {
            any = true;
            if (c == '\n') break;
            if (line.size() < (1u << 20)) line.push_back(static_cast<char>(c));
        }
        if (!any) return Value::integer(static_cast<long long>(i) == 0 ? -1 : 0);
        if (!line.empty() && line.back() == '\r') line.pop_back();
        arr.items[static_cast<size_t>(i)] = Value::string(line);
    }
    return Value::integer(0);
}

Value f_close(Runtime& rt, A, int, L loc) {
    rt.spend(kFileFishSteps, loc);
    if (!rt.file) return Value::integer(1);
    const int r = std::fclose(rt.file);
    const int e = errno;
    rt.file = nullptr;
    if (r != 0) rt.host.err() << "warning: FISH close of '" << rt.file_name << "': " << std::strerror(e) << "\n";
    return Value::integer(r == 0 ? 0 : 1);
}

Value f_lose_array(Runtime&, A a, int, L loc) {
    Array& arr = array_arg(a, "lose_array", loc);
    arr.items.clear();
    arr.items.shrink_to_fit();
    arr.dims.assign(arr.dims.size(), 0);
    return Value::integer(0);
}

Value f_array_size(Runtime&, A a, int n, L loc) {
    Array& arr = array_arg(a, "array_size", loc);
    const long long d = n > 1 ? int_arg(a, 1, "array_size", loc) : 1;
    if (d < 1 || d > static_cast<long long>(arr.dims.size())) fish_fail(loc, "'array_size': the array has no dimension " + std::to_string(d));
    return Value::integer(arr.dims[static_cast<size_t>(d - 1)]);
}

Value f_error(Runtime&, A, int, L) { return Value::string(""); }
void s_error(Runtime&, A, int, const Value& v, L loc) { fish_fail(loc, to_text(v)); }

} // namespace

const std::vector<Intrinsic>& io_intrinsics() {
    static const std::vector<Intrinsic> t = {
        {"error", 0, 0, "", "assigned a string (error = 'text'), stops the function and the script with that message", "io", f_error, s_error},
        {"out", 1, 1, "s", "print s (any value) on a line of its own; gives 0", "io", f_out, nullptr},
        {"open", 1, 3, "name,mode,type", "open a file: mode 0 read, 1 write; type 1 text (0 is read as 1); gives 0 when open, 1 when not (a named pipe or a directory is refused, and for reading a device or a file above 64 MiB)", "io", f_open, nullptr},
        {"write", 1, 2, "array,n", "write the first n elements of the array, one per line, to the open file; gives 0, or 1 when they could not be written (a full disk)", "io", f_write, nullptr},
        {"read", 1, 2, "array,n", "read n lines of the open file into the array as strings; gives 0, or -1 at the file's end", "io", f_read, nullptr},
        {"close", 0, 0, "", "close the open file; gives 0", "io", f_close, nullptr},
        {"lose_array", 1, 1, "array", "free the memory of an array (its name remains, with no elements)", "io", f_lose_array, nullptr},
        {"array_size", 1, 2, "array,dim", "number of elements of the array along dimension dim (default 1)", "io", f_array_size, nullptr},
    };
    return t;
}

} // namespace odec::fish
