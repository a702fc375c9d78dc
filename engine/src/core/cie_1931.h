// The CIE 1931 2-degree standard observer and the XYZ -> scene-linear conversion: spectra
// to colour (blackbody emission, the Nishita sky).
#pragma once
#include "core/math.h"

namespace rdv::cie {

// The 1 nm colour matching functions (CIE 015:2018) sampled every 5 nm from 360 to 830 nm.
constexpr int kSamples = 95;
constexpr double kFirstNm = 360, kStepNm = 5;
extern const double kX[kSamples], kY[kSamples], kZ[kSamples];

// The sample at wavelength nm (a multiple of 5 in [360, 830]).
inline int index_of(double nm) { return int((nm - kFirstNm) / kStepNm + 0.5); }

// XYZ -> linear Rec.709 (D65 white): Blender's scene-linear space, the inverse of its
// colour management's srgb_to_xyz matrix (what Cycles 3.4 derives from the config).
inline void xyz_to_rec709(double X, double Y, double Z, double &r, double &g, double &b) {
  r = 3.2404542 * X - 1.5371385 * Y - 0.4985314 * Z;
  g = -0.9692660 * X + 1.8760108 * Y + 0.0415560 * Z;
  b = 0.0556434 * X - 0.2040259 * Y + 1.0572252 * Z;
}

}  // namespace rdv::cie
