#include "physik/model/params.h"

#include "physik/model/errors.h"

namespace physik {

const char* to_string(SpringLaw s) { return s == SpringLaw::kLinear ? "linear" : "capped"; }

const char* to_string(Integration s) {
  return s == Integration::kArticulated ? "articulated" : "free-rods";
}

const char* to_string(Interpolation s) {
  switch (s) {
    case Interpolation::kNone: return "none";
    case Interpolation::kLinear: return "linear";
    case Interpolation::kPolarHead: return "polar-head";
    case Interpolation::kPolarCom: return "polar-com";
  }
  return "?";
}

const char* to_string(JointSolve s) {
  return s == JointSolve::kGaussSeidel ? "gauss-seidel" : "exact";
}

EngineParams preset_params(const std::string& name, const std::string& source) {
  EngineParams p;  // the original code's values
  p.preset = name;
  if (name == "original") return p;
  if (name == "paper") {
    p.damping = 20.0;
    p.control_k = 30.0;
    return p;
  }
  throw_input_error(source, "params", "preset", "unknown preset '" + name + "' (paper|original)");
}

}  // namespace physik
