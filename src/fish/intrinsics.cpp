#include "fish/intrinsics.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>

#include "fish/runtime.h"

namespace odec::fish {

namespace {

const std::map<std::string, const Intrinsic*>& by_name() {
    static const std::map<std::string, const Intrinsic*> table = [] {
        std::map<std::string, const Intrinsic*> t;
        for (const auto* list : {&math_intrinsics(), &io_intrinsics(), &model_intrinsics()}) {
            for (const Intrinsic& in : *list) t.emplace(in.name, &in);
        }
        return t;
    }();
    return table;
}

} // namespace

const Intrinsic* find_intrinsic(const std::string& lower_name) {
    const auto& t = by_name();
    auto it = t.find(lower_name);
    return it == t.end() ? nullptr : it->second;
}

const std::vector<const Intrinsic*>& all_intrinsics() {
    static const std::vector<const Intrinsic*> all = [] {
        std::vector<const Intrinsic*> v;
        for (const auto& [k, in] : by_name()) v.push_back(in);
        std::stable_sort(v.begin(), v.end(), [](const Intrinsic* a, const Intrinsic* b) {
            const int g = std::strcmp(a->group, b->group);
            return g != 0 ? g < 0 : std::strcmp(a->name, b->name) < 0;
        });
        return v;
    }();
    return all;
}

double num_arg(const Value* a, int i, const char* fn, const SourceLoc& loc) {
    if (!a[i].is_number()) {
        fish_fail(loc, std::string("'") + fn + "' needs a number as argument " + std::to_string(i + 1) + ", not " + type_name(a[i]));
    }
    return a[i].number();
}

long long int_arg(const Value* a, int i, const char* fn, const SourceLoc& loc) {
    if (a[i].type == Type::Int) return a[i].i;
    if (a[i].type == Type::Float && a[i].f == std::floor(a[i].f) && std::fabs(a[i].f) < 9e15) return static_cast<long long>(a[i].f);
    fish_fail(loc, std::string("'") + fn + "' needs a whole number as argument " + std::to_string(i + 1) + ", not " +
                       (a[i].is_number() ? to_text(a[i]) : std::string(type_name(a[i]))));
}

std::string str_arg(const Value* a, int i, const char* fn, const SourceLoc& loc) {
    if (a[i].type != Type::String) {
        fish_fail(loc, std::string("'") + fn + "' needs a string as argument " + std::to_string(i + 1) + ", not " + type_name(a[i]));
    }
    return a[i].s;
}

Eigen::Vector3d point_args(const Value* a, int n, int i, const char* fn, const SourceLoc& loc) {
    if (n - i == 1 && a[i].type == Type::Vector) return a[i].v;
    if (n - i == 3) return {num_arg(a, i, fn, loc), num_arg(a, i + 1, fn, loc), num_arg(a, i + 2, fn, loc)};
    fish_fail(loc, std::string("'") + fn + "' needs a point: three numbers x,y,z or one vector");
}

} // namespace odec::fish
