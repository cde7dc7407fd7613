// What pictures and exports need to know about contacts, as plain arrays.
//
// The contact code fills a ContactView (one row per contact, and optionally one row per
// sub-contact); `plot contact ...`, `plot principal` and `export vtk` read only this. It
// keeps pictures and files independent of how contacts are stored inside the cycle, and
// lets the tests build contacts by hand. No VTK here.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Dense>

namespace odec {

struct ContactRows {
    std::vector<Eigen::Vector3d> centroid;     // (n) m, on the common plane
    std::vector<Eigen::Vector3d> normal;       // (n) unit, from block1 towards block2
    std::vector<double> area;                  // (n) m^2 (share of face area for sub-contacts)
    std::vector<int> block1, block2;           // (n) block ids (not indices)
    std::vector<double> normal_stress;         // (n) Pa, compression positive
    std::vector<Eigen::Vector3d> shear_stress; // (n) Pa, in the plane
    std::vector<double> normal_disp;           // (n) m, closure positive (compression)
    std::vector<Eigen::Vector3d> shear_disp;   // (n) m, accumulated, in the plane
    std::vector<Eigen::Vector3d> force;        // (n) N, on block2 from block1
    std::vector<int> state;                    // (n) index into ContactView::state_names
    std::vector<int> parent;                   // (n) sub-contacts only: row of its contact
    std::vector<double> pore_pressure;         // (n) Pa, fluid flow ('config flow'): of the node, or the
                                               //     contact's mean over its sub-contacts
    std::vector<double> aperture;              // (n) m, hydraulic aperture (likewise)

    int size() const { return static_cast<int>(centroid.size()); }
};

struct ContactView {
    ContactRows contacts;
    ContactRows sub_contacts;                  // may be empty
    // Names of the states, e.g. {"elastic", "slipping", "slipped before", "tension failed"}.
    std::vector<std::string> state_names;
};

// Rows are complete when normal and area have the length of `centroid` and every other
// array has it too or is empty (a quantity the contact code does not provide).
// Inline: both the render and the io library read contact views.
inline bool contact_rows_valid(const ContactRows& r, std::string& error) {
    const size_t n = r.centroid.size();
    auto check = [&](size_t size, const char* name, bool optional) {
        if (size == n || (optional && size == 0)) return true;
        error = std::string("contact rows: '") + name + "' has " + std::to_string(size) + " entries, expected " +
                std::to_string(n);
        return false;
    };
    return check(r.normal.size(), "normal", false) && check(r.area.size(), "area", false) &&
           check(r.block1.size(), "block1", true) && check(r.block2.size(), "block2", true) &&
           check(r.normal_stress.size(), "normal_stress", true) && check(r.shear_stress.size(), "shear_stress", true) &&
           check(r.normal_disp.size(), "normal_disp", true) && check(r.shear_disp.size(), "shear_disp", true) &&
           check(r.force.size(), "force", true) && check(r.state.size(), "state", true) &&
           check(r.parent.size(), "parent", true) && check(r.pore_pressure.size(), "pore_pressure", true) &&
           check(r.aperture.size(), "aperture", true);
}

} // namespace odec
