// A structure-aware script generator for the interpreter's fuzzing target: the bytes of an
// input are a stream of choices, and the generator turns them into a well-formed odec script
// built from the command declarations (commands, keywords, values of the declared types
// inside or just outside their limits, range phrases) and from FISH (functions with loops,
// `command ... endcommand` blocks, `whilestepping` functions), most of the time after a small
// model (a brick on a joint, properties, gravity). Random bytes thus reach the handlers and
// the cycle instead of stopping at the parser, and a mutation of one byte changes one choice.
//
// The same bytes always give the same script (no clock, no random source, no addresses).
// When the bytes run out every further choice is its first option: the script ends soon.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "lang/parser.h"

namespace odec::fuzz {

// An input of the interpreter target whose first byte is this is decoded by the generator;
// any other input is script text. (No script starts with a control character.)
constexpr std::uint8_t kGeneratorMarker = 0x01;

struct GeneratedScript {
    std::string text;                                       // the script
    std::vector<std::pair<std::string, std::string>> files; // files it calls: name, contents
};

// The script the choices give (the marker byte already taken off).
GeneratedScript generate_script(const std::uint8_t* choices, std::size_t size, const CommandTable& table);

// For a person: the files the harness writes (as comments), then the script.
std::string printable(const GeneratedScript& g);

} // namespace odec::fuzz
