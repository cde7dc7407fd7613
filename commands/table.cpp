#include "commands.h"
#include "common.h"

#include <cctype>
#include <cmath>
#include <sstream>

namespace odec {

const CommandSpec& table_command() {
    static const CommandSpec spec = [] {
        CommandSpec c("table", 3, "define a piecewise-linear table of (x, y) points");
        c.positional.integer("n", 1, 1000000).real("x y").optional().repeat();
        c.keyword("read", 3, "read the points from a text file: two numbers a line").string("file");
        c.keyword("delete", 3, "remove the table");
        c.describe("Points follow the table number as x1 y1 x2 y2 ...; x must increase. Between points the "
                   "value is linear, beyond the ends it is held. Tables drive boundary velocities, loads and "
                   "stresses in time ('bound ... hist table n'): x is then the model time, s (not real time in "
                   "a static analysis), y the factor on the value given. A boundary condition whose table is "
                   "deleted is 0 from then on.");
        c.example("table 1 0,0 0.5,1 1,0");
        c.handle([](CommandContext& ctx, const Args& a) {
            Model& m = ctx.model;
            const int n = static_cast<int>(a.positional[0].number);
            if (a.has("delete")) {
                if (a.positional.size() > 1 || a.has("read")) fail(a.find("delete")->loc, "'delete' takes no points", {}, "table");
                m.tables.tables.erase(n);
                // What followed the table is now 0: say so.
                int users = 0;
                const BlockSet& s = m.blocks;
                for (int b = 0; b < s.size(); ++b) {
                    users += s.vel_bc[b] && s.vel_bc_table[b] == n ? 1 : 0;
                    for (const BlockLoad& l : s.loads[b]) users += l.table == n ? 1 : 0;
                }
                const GridpointSet& g = m.gridpoints;
                for (int i = 0; i < g.size(); ++i) {
                    users += (g.vel_bc[i] && g.vel_bc_table[i] == n) || g.applied_table[i] == n ? 1 : 0;
                }
                for (const BoundaryFace& f : m.stress_boundary.faces) users += f.table == n ? 1 : 0;
                if (users > 0) {
                    warn(ctx, a.find("delete")->loc,
                         std::to_string(users) + " boundary condition" + (users == 1 ? "" : "s") + " ('bound ... hist table " +
                             std::to_string(n) + "') followed table " + std::to_string(n) + (users == 1 ? ": it is" : ": they are") + " 0 from now on");
                }
                return;
            }
            Table t;
            if (a.has("read")) {
                const Value& f = a.find("read")->values[0];
                const std::string path = relative_to_script(f.loc, f.text);
                check_file_allowed(ctx, f.loc, path, "table");
                std::string text, why;
                if (!read_file_text(path, text, why)) fail(f.loc, "cannot open '" + f.text + "': " + why, {}, "table");
                std::istringstream in(text);
                std::string line;
                int line_no = 0;
                while (std::getline(in, line)) {
                    ++line_no;
                    for (char& ch : line) {
                        if (ch == ',' || ch == '\t' || ch == ';') ch = ' ';
                    }
                    std::istringstream ls(line);
                    double x, y;
                    const auto bad = [&] {
                        fail(f.loc, "'" + f.text + "' line " + std::to_string(line_no) + ": expected two finite numbers",
                             {}, "table");
                    };
                    if (!(ls >> x)) {
                        // A number too large for a double fails to read too: that is no comment.
                        const size_t k = line.find_first_not_of(' ');
                        const size_t d = k != std::string::npos && (line[k] == '+' || line[k] == '-' || line[k] == '.') ? k + 1 : k;
                        if (d < line.size() && std::isdigit(static_cast<unsigned char>(line[d]))) bad();
                        continue; // blank or comment line
                    }
                    if (!(ls >> y) || !std::isfinite(x) || !std::isfinite(y)) bad();
                    // As for typed numbers: beyond 1e100 what odec derives from them overflows.
                    if (std::abs(x) > kMaxMagnitude || std::abs(y) > kMaxMagnitude) {
                        fail(f.loc, "'" + f.text + "' line " + std::to_string(line_no) +
                                        ": numbers must be of magnitude at most 1e100, as typed ones are",
                             {}, "table");
                    }
                    t.points.emplace_back(x, y);
                }
            }
            const size_t n_values = a.positional.size() - 1;
            if (n_values % 2 != 0) {
                fail(a.positional.back().loc, "table points come in pairs x y: this x has no y", {}, "table");
            }
            for (size_t k = 1; k + 1 < a.positional.size(); k += 2) {
                t.points.emplace_back(a.positional[k].number, a.positional[k + 1].number);
            }
            for (size_t k = 1; k < t.points.size(); ++k) {
                if (!(t.points[k].first > t.points[k - 1].first)) {
                    const SourceLoc loc = n_values > 0 && 2 * k + 1 < a.positional.size() ? a.positional[2 * k + 1].loc : a.loc;
                    fail(loc, "table x values must increase (point " + std::to_string(k + 1) + ": " +
                                  num(t.points[k].first) + " after " + num(t.points[k - 1].first) + ")",
                         {}, "table");
                }
            }
            if (t.points.empty()) fail(a.loc, "table " + std::to_string(n) + " needs points (x y ...) or 'read file'", {}, "table");
            m.tables.tables[n] = std::move(t);
        });
        return c;
    }();
    return spec;
}

} // namespace odec
