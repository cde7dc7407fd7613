// Numbers, vectors, strings and types. Angles of sin, cos, tan, asin, acos, atan and atan2 are
// in radians, as in the classic dialect; `degrad` converts degrees to radians.
#include <cmath>
#include <cstdlib>
#include <random>

#include "fish/intrinsics.h"
#include "fish/runtime.h"

namespace odec::fish {

namespace {

using A = const Value*;
using L = const SourceLoc&;

Value finite(double x, const char* fn, L loc) {
    if (!std::isfinite(x)) fish_fail(loc, std::string("'") + fn + "' has no finite value here (" + (std::isnan(x) ? "nan" : "inf") + ")");
    return Value::real(x);
}

Value f_abs(Runtime&, A a, int, L loc) {
    if (a[0].type == Type::Int) return a[0].i == INT64_MIN ? Value::real(-static_cast<double>(a[0].i)) : Value::integer(std::llabs(a[0].i));
    return Value::real(std::fabs(num_arg(a, 0, "abs", loc)));
}
Value f_sqrt(Runtime&, A a, int, L loc) {
    const double x = num_arg(a, 0, "sqrt", loc);
    if (x < 0) fish_fail(loc, "'sqrt' of a negative number (" + to_text(a[0]) + ")");
    return Value::real(std::sqrt(x));
}
Value f_sin(Runtime&, A a, int, L loc) { return finite(std::sin(num_arg(a, 0, "sin", loc)), "sin", loc); }
Value f_cos(Runtime&, A a, int, L loc) { return finite(std::cos(num_arg(a, 0, "cos", loc)), "cos", loc); }
Value f_tan(Runtime&, A a, int, L loc) { return finite(std::tan(num_arg(a, 0, "tan", loc)), "tan", loc); }
Value f_asin(Runtime&, A a, int, L loc) { return finite(std::asin(num_arg(a, 0, "asin", loc)), "asin", loc); }
Value f_acos(Runtime&, A a, int, L loc) { return finite(std::acos(num_arg(a, 0, "acos", loc)), "acos", loc); }
Value f_atan(Runtime&, A a, int, L loc) { return Value::real(std::atan(num_arg(a, 0, "atan", loc))); }
Value f_atan2(Runtime&, A a, int, L loc) { return Value::real(std::atan2(num_arg(a, 0, "atan2", loc), num_arg(a, 1, "atan2", loc))); }
Value f_exp(Runtime&, A a, int, L loc) { return finite(std::exp(num_arg(a, 0, "exp", loc)), "exp", loc); }
Value f_ln(Runtime&, A a, int, L loc) {
    const double x = num_arg(a, 0, "ln", loc);
    if (x <= 0) fish_fail(loc, "'ln' of a number that is not positive (" + to_text(a[0]) + ")");
    return Value::real(std::log(x));
}
Value f_log(Runtime&, A a, int, L loc) {
    const double x = num_arg(a, 0, "log", loc);
    if (x <= 0) fish_fail(loc, "'log' of a number that is not positive (" + to_text(a[0]) + ")");
    return Value::real(std::log10(x));
}
Value f_sgn(Runtime&, A a, int, L loc) {
    const double x = num_arg(a, 0, "sgn", loc);
    return Value::integer(x > 0 ? 1 : x < 0 ? -1 : 0);
}
Value minmax(A a, int n, L loc, bool want_max, const char* fn) {
    Value best = a[0];
    num_arg(a, 0, fn, loc);
    for (int k = 1; k < n; ++k) {
        num_arg(a, k, fn, loc);
        const bool better = want_max ? a[k].number() > best.number() : a[k].number() < best.number();
        if (better) best = a[k];
    }
    // Mixed integers and floats give a float, as arithmetic does.
    for (int k = 0; k < n; ++k) {
        if (a[k].type == Type::Float) return Value::real(best.number());
    }
    return best;
}
Value f_min(Runtime&, A a, int n, L loc) { return minmax(a, n, loc, false, "min"); }
Value f_max(Runtime&, A a, int n, L loc) { return minmax(a, n, loc, true, "max"); }
Value f_pi(Runtime&, A, int, L) { return Value::real(M_PI); }
Value f_degrad(Runtime&, A, int, L) { return Value::real(M_PI / 180.0); }
double read_number(const std::string& s, const char* fn, L loc) {
    char* end = nullptr;
    const double x = std::strtod(s.c_str(), &end);
    if (end == s.c_str()) fish_fail(loc, std::string("'") + fn + "' cannot read a number from '" + s + "'");
    return x;
}
Value f_float(Runtime&, A a, int, L loc) {
    if (a[0].type == Type::String) return Value::real(read_number(a[0].s, "float", loc));
    return Value::real(num_arg(a, 0, "float", loc));
}
Value f_int(Runtime&, A a, int, L loc) {
    double x = 0;
    if (a[0].type == Type::String) {
        x = read_number(a[0].s, "int", loc);
    } else {
        x = num_arg(a, 0, "int", loc);
    }
    if (!std::isfinite(x) || std::fabs(x) >= 9.2e18) fish_fail(loc, "'int' of a number too large for an integer (" + to_text(Value::real(x)) + ")");
    return Value::integer(static_cast<long long>(std::trunc(x)));
}
Value f_round(Runtime&, A a, int, L loc) {
    const double x = num_arg(a, 0, "round", loc);
    if (!std::isfinite(x) || std::fabs(x) >= 9.2e18) fish_fail(loc, "'round' of a number too large for an integer");
    return Value::integer(static_cast<long long>(std::llround(x)));
}
Value f_string(Runtime&, A a, int, L) { return Value::string(to_text(a[0])); }
Value f_strlen(Runtime&, A a, int, L loc) { return Value::integer(static_cast<long long>(str_arg(a, 0, "strlen", loc).size())); }
Value f_substr(Runtime&, A a, int, L loc) {
    const std::string s = str_arg(a, 0, "substr", loc);
    const long long from = int_arg(a, 1, "substr", loc), len = int_arg(a, 2, "substr", loc);
    if (from < 1 || len < 0) fish_fail(loc, "'substr' starts at 1 and takes a length >= 0");
    if (static_cast<size_t>(from) > s.size()) return Value::string("");
    return Value::string(s.substr(static_cast<size_t>(from - 1), static_cast<size_t>(len)));
}
Value f_type(Runtime&, A a, int, L) {
    // 1 integer, 2 float, 3 string, 4 pointer, 5 vector, 6 boolean, 7 array.
    static const int code[] = {1, 2, 6, 3, 5, 4, 7};
    return Value::integer(code[static_cast<int>(a[0].type)]);
}
Value f_vector(Runtime&, A a, int n, L loc) { return Value::vector(point_args(a, n, 0, "vector", loc)); }
Value vec0(A a, const char* fn, L loc) {
    if (a[0].type != Type::Vector) fish_fail(loc, std::string("'") + fn + "' needs a vector, not " + type_name(a[0]));
    return a[0];
}
Value f_mag(Runtime&, A a, int, L loc) { return Value::real(vec0(a, "mag", loc).v.norm()); }
Value f_unit(Runtime&, A a, int, L loc) {
    const Eigen::Vector3d v = vec0(a, "unit", loc).v;
    if (v.norm() == 0) fish_fail(loc, "'unit' of a zero vector");
    return Value::vector(v.normalized());
}
Value f_dot(Runtime&, A a, int, L loc) { return Value::real(vec0(a, "dot", loc).v.dot(vec0(a + 1, "dot", loc).v)); }
Value f_cross(Runtime&, A a, int, L loc) { return Value::vector(vec0(a, "cross", loc).v.cross(vec0(a + 1, "cross", loc).v)); }
Value f_xcomp(Runtime&, A a, int, L loc) { return Value::real(vec0(a, "xcomp", loc).v.x()); }
Value f_ycomp(Runtime&, A a, int, L loc) { return Value::real(vec0(a, "ycomp", loc).v.y()); }
Value f_zcomp(Runtime&, A a, int, L loc) { return Value::real(vec0(a, "zcomp", loc).v.z()); }

// Random numbers from a fixed seed, so that a script gives the same numbers every run.
std::mt19937_64& rng(Runtime& rt) {
    return rt.random;
}
Value f_urand(Runtime& rt, A, int, L) { return Value::real(std::uniform_real_distribution<double>(0, 1)(rng(rt))); }
Value f_grand(Runtime& rt, A, int, L) { return Value::real(std::normal_distribution<double>(0, 1)(rng(rt))); }

} // namespace

const std::vector<Intrinsic>& math_intrinsics() {
    static const std::vector<Intrinsic> t = {
        {"abs", 1, 1, "x", "absolute value of x", "math", f_abs, nullptr},
        {"sqrt", 1, 1, "x", "square root of x (x >= 0)", "math", f_sqrt, nullptr},
        {"sin", 1, 1, "a", "sine of a (a in radians)", "math", f_sin, nullptr},
        {"cos", 1, 1, "a", "cosine of a (a in radians)", "math", f_cos, nullptr},
        {"tan", 1, 1, "a", "tangent of a (a in radians)", "math", f_tan, nullptr},
        {"asin", 1, 1, "x", "arc sine of x, in radians", "math", f_asin, nullptr},
        {"acos", 1, 1, "x", "arc cosine of x, in radians", "math", f_acos, nullptr},
        {"atan", 1, 1, "x", "arc tangent of x, in radians", "math", f_atan, nullptr},
        {"atan2", 2, 2, "y,x", "angle of the point (x,y) from the x axis, in radians (-pi to pi)", "math", f_atan2, nullptr},
        {"exp", 1, 1, "x", "e to the power x", "math", f_exp, nullptr},
        {"ln", 1, 1, "x", "natural logarithm of x (x > 0)", "math", f_ln, nullptr},
        {"log", 1, 1, "x", "logarithm of x to base 10 (x > 0)", "math", f_log, nullptr},
        {"sgn", 1, 1, "x", "sign of x: 1, 0 or -1", "math", f_sgn, nullptr},
        {"min", 2, 8, "x,y,...", "smallest of its arguments", "math", f_min, nullptr},
        {"max", 2, 8, "x,y,...", "largest of its arguments", "math", f_max, nullptr},
        {"pi", 0, 0, "", "3.14159...", "math", f_pi, nullptr},
        {"degrad", 0, 0, "", "pi/180: multiply degrees by it to get radians", "math", f_degrad, nullptr},
        {"float", 1, 1, "x", "x as a float (a string is read as a number)", "math", f_float, nullptr},
        {"int", 1, 1, "x", "x as an integer, truncated toward zero", "math", f_int, nullptr},
        {"round", 1, 1, "x", "the integer nearest x", "math", f_round, nullptr},
        {"urand", 0, 0, "", "a random number uniform in [0,1) (the same sequence every run)", "math", f_urand, nullptr},
        {"grand", 0, 0, "", "a random number of the standard normal distribution (same sequence every run)", "math", f_grand, nullptr},
        {"string", 1, 1, "x", "x as text (floats in their shortest exact form, vectors as (x,y,z))", "string", f_string, nullptr},
        {"strlen", 1, 1, "s", "number of characters of s", "string", f_strlen, nullptr},
        {"substr", 3, 3, "s,from,n", "n characters of s from position from (1-based)", "string", f_substr, nullptr},
        {"type", 1, 1, "x", "type of x: 1 integer, 2 float, 3 string, 4 pointer, 5 vector, 6 boolean, 7 array", "string", f_type, nullptr},
        {"vector", 1, 3, "x,y,z | v", "the vector (x,y,z)", "vector", f_vector, nullptr},
        {"mag", 1, 1, "v", "length of the vector v", "vector", f_mag, nullptr},
        {"unit", 1, 1, "v", "v divided by its length", "vector", f_unit, nullptr},
        {"dot", 2, 2, "u,v", "scalar product of two vectors", "vector", f_dot, nullptr},
        {"cross", 2, 2, "u,v", "vector product u x v", "vector", f_cross, nullptr},
        {"xcomp", 1, 1, "v", "x component of the vector v", "vector", f_xcomp, nullptr},
        {"ycomp", 1, 1, "v", "y component of the vector v", "vector", f_ycomp, nullptr},
        {"zcomp", 1, 1, "v", "z component of the vector v", "vector", f_zcomp, nullptr},
    };
    return t;
}

} // namespace odec::fish
