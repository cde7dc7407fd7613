// FISH values: integers, floats, booleans, strings, 3-vectors and pointers to model objects.
//
// Arithmetic follows the classic dialect: integer op integer stays integer (division truncates),
// anything with a float is a float, `^` is the power. A pointer is a handle on a block, a
// contact, a sub-contact, a gridpoint or a zone; 0 (the integer) stands for "no object", so
// `loop while ci # 0` ends a walk.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Dense>

namespace odec::fish {

enum class Type : std::uint8_t { Int, Float, Bool, String, Vector, Pointer, Array };

struct Array;

enum class PtrKind : std::uint8_t { Block, Contact, Sub, Gridpoint, Zone };

struct Value {
    Type type = Type::Int;
    PtrKind kind = PtrKind::Block; // for Pointer
    std::int64_t i = 0;            // Int, Bool (0/1), Pointer: index of the object
    std::int32_t scope = -1;       // Pointer: walk within this block or contact (-1: the whole model)
    double f = 0;                  // Float
    Eigen::Vector3d v = Eigen::Vector3d::Zero(); // Vector
    std::string s;                 // String
    std::shared_ptr<Array> a;      // Array (a whole array passed by name, as to write())

    static Value integer(std::int64_t x) { Value r; r.type = Type::Int; r.i = x; return r; }
    static Value real(double x) { Value r; r.type = Type::Float; r.f = x; return r; }
    static Value boolean(bool b) { Value r; r.type = Type::Bool; r.i = b ? 1 : 0; return r; }
    static Value string(std::string x) { Value r; r.type = Type::String; r.s = std::move(x); return r; }
    static Value vector(const Eigen::Vector3d& x) { Value r; r.type = Type::Vector; r.v = x; return r; }
    static Value pointer(PtrKind k, std::int64_t index, std::int32_t scope = -1) {
        Value r; r.type = Type::Pointer; r.kind = k; r.i = index; r.scope = scope; return r;
    }
    static Value null() { return integer(0); }

    bool is_number() const { return type == Type::Int || type == Type::Float; }
    bool is_null() const { return type == Type::Int && i == 0; }
    double number() const { return type == Type::Float ? f : static_cast<double>(i); }
};

// "integer", "float", ... for messages.
const char* type_name(const Value& v);
// How string() and out() show a value: integers as typed, floats in the shortest form that
// reads back to the same number, vectors as (x,y,z), pointers by their object's id.
std::string to_text(const Value& v);

// A FISH array: 1 to 3 dimensions, 1-based indices, any values.
struct Array {
    std::vector<int> dims;
    std::vector<Value> items;
};

} // namespace odec::fish
