#include "lang/not_yet.h"

namespace odec {

namespace {

struct Missing {
    const char* word;
    const char* what;
};

// Sorted by nothing but reading order; each is matched by a prefix of 3 letters or more.
const Missing kMissing[] = {
    {"gridpoint", "the 'gridpoint' command is not available: gridpoints of deformable blocks are held with 'fix' "
                  "and 'bound ...vel', loaded with 'bound', listed with 'print gp' and recorded with 'hist'"},
    {"structure", "the 'structure' command is not available: fully grouted cables and rock bolts are made with "
                  "'cable' (see 'help cable'), liners and shotcrete with 'liner' (see 'help liner'); beams and "
                  "piles are not available yet"},
    {"water", "the 'water' command is not available: 3DEC's water table without flow (hydrostatic pore pressure "
              "in zones and joints) has no counterpart; odec keeps pore pressures in the joints' flow nodes only: "
              "'config flow', 'fluid density rho', then 'insitu wtable z' (or 'bound wtable z range ...' to hold "
              "it), see 'help fluid'"},
    {"pfix", "odec has no 'pfix' command: a joint pressure is fixed with 'bound pp p [pgrad gx,gy,gz] range ...' "
             "(or 'bound wtable z range ...' for a hydrostatic one) and released with 'bound pfree range ...', "
             "after 'config flow'; see 'help fluid'"},
};

} // namespace

std::string not_yet_available(const std::string& w) {
    if (w.size() < 3 && w != "gp") return "";
    if (w == "gp") return kMissing[0].what;
    for (const Missing& m : kMissing) {
        const std::string full = m.word;
        if (w.size() <= full.size() && full.compare(0, w.size(), w) == 0) return m.what;
    }
    return "";
}

} // namespace odec
