// FISH intrinsics: one declaration each, from which the compiler resolves calls, `help fish`
// lists them and the manual's FISH chapter is written.
//
//   {"sqrt", 1, 1, "x", "square root of x (x >= 0)", "math", get_sqrt, nullptr}
#pragma once

#include <string>
#include <vector>

#include "fish/value.h"
#include "lang/source.h"

namespace odec::fish {

class Runtime;

struct Intrinsic {
    const char* name;
    int min_args;
    int max_args;             // -1: any number
    const char* args;         // for help: "x", "b", "x,y,z | v"
    const char* help;         // one line: what it gives, in which unit and sign
    const char* group;        // math, string, io, block, contact, gridpoint, zone, model
    Value (*get)(Runtime& rt, const Value* a, int n, const SourceLoc& loc);
    // `name(args) = value`; nullptr when read-only.
    void (*set)(Runtime& rt, const Value* a, int n, const Value& v, const SourceLoc& loc);
};

// The declaration of `name` (lower case), or nullptr.
const Intrinsic* find_intrinsic(const std::string& lower_name);
// All of them, sorted by group then name.
const std::vector<const Intrinsic*>& all_intrinsics();

// The tables, one per file.
const std::vector<Intrinsic>& math_intrinsics();
const std::vector<Intrinsic>& io_intrinsics();
const std::vector<Intrinsic>& model_intrinsics();

// Helpers for intrinsic bodies: the argument as a number / integer / vector / string, or an
// error naming the intrinsic's argument.
double num_arg(const Value* a, int i, const char* fn, const SourceLoc& loc);
long long int_arg(const Value* a, int i, const char* fn, const SourceLoc& loc);
std::string str_arg(const Value* a, int i, const char* fn, const SourceLoc& loc);
// A point given as one vector or as three numbers starting at argument i.
Eigen::Vector3d point_args(const Value* a, int n, int i, const char* fn, const SourceLoc& loc);

} // namespace odec::fish
