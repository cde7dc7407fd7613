// Zone constitutive models: stress increments from strain increments.
//
// Elastic (model 1): isotropic, bulk modulus K and shear modulus G:
//   d sigma = 2 G d eps + (K - 2G/3) tr(d eps) I.
//
// Mohr-Coulomb (model 2) with tension cut-off and non-associated flow, in principal stresses
// s1 <= s2 <= s3 (tension positive, s1 the most compressive):
//   shear yield     f_s = s1 - s3 N_phi + 2 c sqrt(N_phi) < 0, N_phi = (1 + sin phi) / (1 - sin phi)
//   tension yield   f_t = s3 - t > 0 (t at most c / tan phi, the apex of the cone)
// An elastic trial stress that violates a criterion is returned to it along the plastic flow
// direction given by the dilation angle psi (N_psi); which criterion governs near the corner
// between the two is decided by the bisector h of the corner in the s1-s3 plane. The return
// is exact for the linear surfaces, so a zone loaded past yield sits exactly on them; the
// rotation back to the axes uses the principal directions of the trial stress.
#pragma once

#include <cstdint>

#include "engine/zones.h"

namespace odec {

struct Material;

struct ZoneMaterialConstants {
    double bulk = 0, shear = 0;   // Pa
    double alpha1 = 0, alpha2 = 0; // K + 4G/3, K - 2G/3
    double cohesion = 0;          // Pa
    double nphi = 1, npsi = 1, sqrt_nphi = 1;
    double tension = 0;           // Pa, the cut-off actually used (at most c / tan phi)
};

ZoneMaterialConstants zone_constants(const Material& mat);

// Add the elastic increment for strain increment de (engineering shear halved: tensor
// components) to s.
void elastic_increment(const ZoneMaterialConstants& c, const Sym6& de, Sym6& s);

// Mohr-Coulomb update: elastic trial then return; returns the ZoneState "now" bits.
std::uint8_t mohr_coulomb_increment(const ZoneMaterialConstants& c, const Sym6& de, Sym6& s);

} // namespace odec
