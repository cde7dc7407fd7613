// Histories: quantities sampled every `ncyc` steps while the model cycles.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include <Eigen/Dense>

namespace odec {

struct Model;

enum class HistoryKind {
    Unbalanced, // largest unbalanced force over the blocks, N
    Time,       // model time, s
    Step,       // step number
    XDis, YDis, ZDis,   // displacement of a material point of a block, m
    XVel, YVel, ZVel,   // velocity of a material point of a block at t, m/s
    Ratio,      // mean unbalanced-force ratio
    NStress, SStress,   // contact normal (compression positive) and shear stress, Pa
    NDis, SDis,         // contact normal closure and shear displacement, m
    SXX, SYY, SZZ, SXY, SXZ, SYZ, // stress of the zone at a point, Pa (tension positive)
    XReaction, YReaction, ZReaction, // sum of the unbalanced forces of the held gridpoints (and fixed
                                     // blocks) of a range, N: what the model exerts on its supports
    NForce, SForce,     // total normal force (compression positive) and shear force magnitude of a contact, N
    XAcc, YAcc, ZAcc,   // acceleration of a material point of a block (or of a gridpoint), m/s^2
    Damp,       // mass-proportional damping coefficient in use, 1/s (0 with local damping or none)
    Fish,       // the value of a FISH variable or function (`hist @name`), in its own unit
    Energy,     // a term of the energy account (`hist energy name`, the name in `source`), J
    CableForce, // axial force of a cable segment, N (tension positive)
    CableGrout, // grout force on a cable node along the cable, N (toward its last node positive)
    PorePressure, // pore pressure of the flow node nearest the point, Pa (flow.h)
    Aperture,   // hydraulic aperture of the flow node nearest the point (mean over its area), m
    FlowRate,   // flow the fixed-pressure boundaries feed into the joints, m^3/s
    LinerNx,    // membrane force n_x of a liner element, N/m (tension positive; liner.h)
    LinerMx,    // bending moment m_x of a liner element, N m/m (void-side face in tension positive)
};

struct History {
    HistoryKind kind = HistoryKind::Unbalanced;
    Eigen::Vector3d point = Eigen::Vector3d::Zero(); // where the user asked (block quantities)
    int block_id = 0;                                // block sampled (block quantities)
    Eigen::Vector3d body_offset = Eigen::Vector3d::Zero(); // m, the sampled material point in the
                                                     // block's body frame, from its centroid
    int contact_id = 0;                              // contact sampled (contact quantities)
    int gridpoint = -1;                              // gridpoint sampled (displacement and velocity
                                                     // in a deformable block), else -1; -2: it was
                                                     // removed with its block (the history reads 0)
    int zone = -1;                                   // zone sampled (stress), else -1; -2: removed
    std::vector<int> gridpoints;                     // reactions: the gridpoints summed
    std::vector<int> blocks;                         // reactions: the rigid block ids summed
    std::string label;                               // column title
    std::string source;                              // Fish: the FISH name sampled; Energy: the term
    int cable_id = 0;                                // cable quantities: the cable's id; liner
                                                     // quantities: the liner's id
    int cable_item = 0;                              // its segment (CableForce) or node (CableGrout),
                                                     // from 1 along the cable; the liner's element,
                                                     // from 1 (LinerNx, LinerMx)
    // Its samples: values[i] was taken at HistorySet::sample_steps[first + i]. A history made
    // while the model already had samples starts with the next one (first > 0); the samples
    // before it are none of its own.
    long first = 0;
    std::vector<double> values;                      // (n_samples - first)
    // Its value at sample k of the set, or nullptr before its first.
    const double* at(size_t k) const {
        return k >= static_cast<size_t>(first) && k - first < values.size() ? &values[k - first] : nullptr;
    }
};

struct HistorySet {
    int ncyc = 10;                  // sampling interval in steps
    std::vector<History> items;     // history n is items[n-1]
    std::vector<long> sample_steps; // (n_samples) step of each sample
    // Reads a Fish history, number `number` (set by the program that runs FISH; not saved): true
    // with its value, or false with what went wrong in `error` (the function failed, or gave no
    // finite number).
    std::function<bool(const History& h, int number, double& value, std::string& error)> external;
    // Record one sample of every history. When a FISH history fails, nothing of this sample is
    // kept and the error says which history and why; else "".
    std::string sample(const Model& m);
    void clear_values();
};

// Current value of one history's quantity (not of a Fish history: HistorySet::external).
double history_value(const Model& m, const History& h);
// Default label, e.g. "zdis (0,0,5) block 1".
std::string history_default_label(const History& h);

} // namespace odec
