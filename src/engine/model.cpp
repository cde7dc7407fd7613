#include "engine/model.h"

#include <algorithm>

namespace odec {

const char* stage_name(Stage s) {
    switch (s) {
    case Stage::ApplyLoads: return "apply_loads";
    case Stage::DetectContacts: return "detect_contacts";
    case Stage::UpdateContacts: return "update_contacts";
    case Stage::Zones: return "zones";
    case Stage::Integrate: return "integrate";
    case Stage::Record: return "record";
    case Stage::Checks: return "checks";
    case Stage::Cables: return "cables";
    case Stage::Flow: return "flow";
    case Stage::Liners: return "liners";
    case Stage::Count: break;
    }
    return "?";
}

int Model::block_index(int block_id) const {
    const auto& ids = blocks.id;
    auto it = std::lower_bound(ids.begin(), ids.end(), block_id);
    if (it == ids.end() || *it != block_id) return -1;
    return static_cast<int>(it - ids.begin());
}

int Model::group_index(const std::string& name, bool create) {
    for (size_t g = 0; g < group_names.size(); ++g) {
        if (group_names[g] == name) return static_cast<int>(g);
    }
    if (!create) return -1;
    group_names.push_back(name);
    return static_cast<int>(group_names.size()) - 1;
}

double Model::table_factor(int table, double t) const {
    if (table <= 0) return 1.0;
    const Table* tab = tables.find(table);
    return tab ? tab->at(t) : 0.0;
}

} // namespace odec
