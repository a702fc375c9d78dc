// Every lobe model with the parameter sets the statistical tests sweep. Adding a
// BSDF means adding its lines here: the chi-square, energy and reciprocity tests
// then cover it without further test code.
#pragma once
#include <string>
#include <vector>
#include "bsdfs/bsdf.h"

namespace rdv {

struct LobeTestCase {
  std::string name;
  Lobe lobe;
  bool energy_conserving;  // white version must reflect everything (within 1%)
  // Cycles 3.4's Disney diffuse reflects more than it receives at grazing angles; it
  // is only used by the Principled BSDF's "additive" layering (Cycles 3.4 exactly).
  bool exceeds_one_by_design = false;
};

const std::vector<LobeTestCase> &lobe_test_cases();

}  // namespace rdv
