// The axis of a tunnel, as 'poly tunnel' and 'tunnel' both take it: 'a (x,y,z) b (x,y,z)', or
// 'length l1 l2' along the line of plunge 'dip' and trend 'dd' through 'origin'.
#pragma once

#include <string>
#include <vector>

#include "common.h"
#include "engine/jset.h"
#include "engine/tunnel.h"

namespace odec {

// Sets spec.a and spec.b from the command's words, or fails naming the word at fault.
// `where` is the word that asked for a tunnel; `topic` the help topic of the command.
inline void read_tunnel_axis(const Args& a, const SourceLoc& where, const std::string& topic, TunnelSpec& spec) {
    const KeywordUse* direction = nullptr;
    for (const char* k : {"dip", "dd", "origin", "length"}) {
        if (!direction && a.has(k)) direction = a.find(k);
    }
    if (a.has("a") || a.has("b")) {
        if (direction) {
            fail(direction->loc,
                 "give the tunnel's axis either by 'a' and 'b' or by 'dip', 'dd', 'origin' and 'length', not both", {},
                 topic);
        }
        if (!a.has("a") || !a.has("b")) fail(where, "the tunnel needs both ends of its axis: 'a (x,y,z) b (x,y,z)'", {}, topic);
        for (const char* k : {"a", "b"}) {
            const KeywordUse* u = a.find(k);
            std::vector<Vec3> points;
            for (const Value& v : u->values) {
                if (v.type == ValueType::Vec3) points.push_back(v.vec);
            }
            if (points.size() != 1) {
                fail(u->values[1].loc, std::string("'") + k + "' takes one point here, an end of the tunnel's axis (got " +
                                           std::to_string(points.size()) + ")",
                     {}, topic);
            }
            (k[0] == 'a' ? spec.a : spec.b) = points[0];
        }
    } else if (a.has("length")) {
        const Vec3 dir = dip_vector(a.real_or("dip", 0), a.real_or("dd", 0));
        const Vec3 origin = a.has("origin") ? a.vec("origin") : Vec3::Zero();
        spec.a = origin + a.real("length", 0) * dir;
        spec.b = origin + a.real("length", 1) * dir;
    } else {
        fail(direction ? direction->loc : where,
             "the tunnel needs its axis: 'a (x,y,z) b (x,y,z)', or 'dip d dd a length l1 l2' (from 'origin', default "
             "0,0,0)",
             {}, topic);
    }
}

} // namespace odec
