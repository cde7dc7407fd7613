#include "io/csv.h"

#include <cerrno>
#include <cstdio>
#include <cstring>

namespace odec {

static std::string quote(const std::string& s) {
    std::string out = "\"";
    for (char c : s) {
        if (c == '"') out += '"';
        out += c;
    }
    return out + "\"";
}

bool write_histories_csv(const HistorySet& h, const std::vector<int>& numbers, int vs,
                         const std::string& path, std::string& error, size_t* rows) {
    const std::string tmp = path + ".tmp";
    FILE* f = std::fopen(tmp.c_str(), "w");
    if (!f) {
        error = "cannot write '" + path + "': " + std::strerror(errno);
        return false;
    }
    std::string header = vs > 0 ? quote(std::to_string(vs) + ": " + h.items[vs - 1].label) : "step";
    for (int n : numbers) header += "," + quote(std::to_string(n) + ": " + h.items[n - 1].label);
    std::fprintf(f, "%s\n", header.c_str());
    size_t written = 0;
    for (size_t k = 0; k < h.sample_steps.size(); ++k) {
        if (vs > 0) {
            const double* x = h.items[vs - 1].at(k);
            if (!x) continue;
            std::fprintf(f, "%.17g", *x);
        } else {
            std::fprintf(f, "%ld", h.sample_steps[k]);
        }
        for (int n : numbers) {
            const double* y = h.items[n - 1].at(k);
            if (y) std::fprintf(f, ",%.17g", *y);
            else std::fputc(',', f);
        }
        std::fprintf(f, "\n");
        ++written;
    }
    if (rows) *rows = written;
    // A full disk shows at the flush, or only at the close on some file systems.
    bool ok = std::fflush(f) == 0 && !std::ferror(f);
    ok = std::fclose(f) == 0 && ok;
    if (!ok || std::rename(tmp.c_str(), path.c_str()) != 0) {
        error = "cannot write '" + path + "': " + std::strerror(errno);
        std::remove(tmp.c_str());
        return false;
    }
    return true;
}

} // namespace odec
