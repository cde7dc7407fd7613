// The factor of safety by strength reduction ('solve fos').
//
// A trial factor F lowers the strengths of the joints and of the Mohr-Coulomb zones:
//   tan(phi_F) = tan(phi) / F,   c_F = c / F,   t_F = t / F
// (a joint model 2's residual friction as its friction), each from its value before the search.
// The dilation angle is kept at most phi_F (non-associated flow), or made phi_F ('associated').
// The factor of safety is the F at which the model just fails: the search brackets it between
// a factor at which it is stable and one at which it fails (FosBracket), each trial starting
// from the same state.
//
// The trial at F is run by the command layer: cycle in runs of Nr steps (the characteristic
// response: the steps the model takes to come back to equilibrium after its stresses were
// doubled with its strengths raised) until the mean unbalanced-force ratio falls below its
// limit (stable) or stops falling (fails).
//
// Numbers only; the command layer words them.
#pragma once

#include <string>
#include <vector>

#include "engine/model.h"
#include "engine/range.h"

namespace odec {

// Which strengths a search lowers.
struct FosTargets {
    bool joints = true, zones = true;                   // kinds
    bool friction = true, cohesion = true, tension = true; // properties (of both kinds)
    bool associated = false; // dilation made equal to the reduced friction
};

// What a search can lower: joint materials in use (by a contact, a joint plane or as the
// default for new contacts) and materials of Mohr-Coulomb zones, with a nonzero strength
// among the targets.
struct FosReducible {
    std::vector<int> joint_materials; // numbers
    std::vector<int> zone_materials;  // numbers
    bool empty() const { return joint_materials.empty() && zone_materials.empty(); }
};
FosReducible fos_reducible(const Model& m, const FosTargets& t);

// A search narrowed to a range: the contacts whose centroid the range selects, and the blocks it
// selects (their zones), are given copies of their joint and zone materials (new numbers, after
// the others), and only the copies are reduced. Contacts made during a trial take the materials
// they would otherwise (not reduced). fos_isolate makes the copies and narrows r to them;
// fos_unisolate gives every contact and block its number back and drops the copies.
struct FosIsolation {
    bool active = false;
    int n_joint_materials = 0, n_materials = 0; // how many there were before the copies
    std::vector<int> joint_original;            // per copy, in order: the number it copies
    std::vector<int> material_original;
};
FosIsolation fos_isolate(Model& m, const Range& range, FosReducible& r);
void fos_unisolate(Model& m, const FosIsolation& iso);

// The strengths before a search, to reduce from and to give back.
struct FosBase {
    std::vector<JointMaterial> joint_materials;
    std::vector<Material> materials;
};
FosBase fos_base(const Model& m);

// Set the strengths of the materials in `r` to their values in `base` reduced by F (> 0).
void reduce_strengths(Model& m, const FosBase& base, const FosReducible& r, const FosTargets& t, double F);
// Give the strengths of `base` back to the materials in `r` (other properties stay as they are).
void restore_strengths(Model& m, const FosBase& base, const FosReducible& r);

// The start of the search for Nr: strengths of the materials in `r` raised so that nothing can
// slip, open or yield, and every joint and zone stress multiplied by `factor` (the normal
// closure and the shear stress of every sub-contact, the stress of every zone).
void perturb_for_response(Model& m, const FosReducible& r, double factor);

// Whether anything loads the model: gravity, a load or stress on a block or gridpoint, or a
// stress already in a zone or a joint (in situ). Without one nothing can fail.
bool fos_model_loaded(const Model& m);

// The bracketing of the factor of safety between a stable and a failing trial.
//
// Without starting values: the first trial is at 1; while stable, the factor doubles, while
// failing it halves, until one of each is known (the first found failing or stable at
// kFosFar or 1 / kFosFar ends the search: the factor is beyond it); then the middle of the
// bracket is tried until the bracket is no wider than the resolution.
// With starting values f1 <= f2: f1 is tried and must be stable, then f2 and must fail (the
// factor is below f1 or above f2 otherwise, and the search ends); with f1 = f2, that one trial.
constexpr double kFosFar = 1024;

class FosBracket {
public:
    // resolution > 0; bracket: f1, f2 (0, 0 when not given).
    FosBracket(double resolution, double f1, double f2);
    // The next factor to try; 0 when the search is over.
    double next() const { return next_; }
    // The outcome of the trial at next().
    void report(bool stable);

    enum class End { Running, Found, Below, Above, OneStable, OneFails };
    End end() const { return end_; }
    bool has_stable() const { return has_stable_; }
    bool has_fail() const { return has_fail_; }
    double stable() const { return stable_; } // the largest factor found stable
    double fails() const { return fail_; }    // the smallest factor found failing
    // The factor of safety: the middle of the final bracket (0 unless Found).
    double factor() const { return end_ == End::Found ? 0.5 * (stable_ + fail_) : 0.0; }

private:
    double resolution_, f1_, f2_;
    bool given_;
    double next_ = 1;
    bool has_stable_ = false, has_fail_ = false;
    double stable_ = 0, fail_ = 0;
    End end_ = End::Running;
    void choose();
};

// What the last search found ('print info', FISH fos_f).
struct FosResult {
    FosBracket::End end = FosBracket::End::Running;
    double factor = 0;      // the factor of safety (Found), else 0
    double stable = 0;      // the largest factor found stable (0: none)
    double fails = 0;       // the smallest factor found failing (0: none)
    double resolution = 0;
    int trials = 0;
    long steps = 0;         // steps of all the trials and of the search for Nr
    long nr = 0;            // the characteristic response, steps
    double seconds = 0;     // wall time
};

} // namespace odec
