// Engine parameters, with the paper's and the original code's presets.
//
// Names are the scene file's "params" keys. Presets (docs/DESIGN.md "The paper", paper Sec. 4, original fwik.py):
//   original: dt 0.05 s, damping 3 N s/m, angular velocity x0.5 per step, eps 1e-3, pass cap
//             5 n^2, control k 10 N/m, torsion k 10 N m/rad engaging 10% inside each limit,
//             linear torsion, articulated integration, linear target interpolation
//   paper:    as original but damping 20 N s/m and control k 30 N/m (paper Sec. 4 / Fig 5)
#pragma once

#include <string>

namespace physik {

enum class SpringLaw { kLinear, kCapped };
enum class Integration { kArticulated, kFreeRods };
enum class Interpolation { kNone, kLinear, kPolarHead, kPolarCom };

const char* to_string(SpringLaw s);
const char* to_string(Integration s);
const char* to_string(Interpolation s);

struct EngineParams {
  std::string preset = "original";
  double dt = 0.05;                      // s, time step
  double damping = 3.0;                  // N s/m, force -c v at each bone end
  double angular_velocity_factor = 0.5;  // 1, every bone's angular velocity is scaled by it each step
  double joint_eps = 1e-3;               // rig units/s^2, stop the joint passes below this mismatch
  // TODO(table): port to the parameter table (issue 12 phase A added it here and in scene_io.cpp)
  double joint_eps_relative = 0.0;       // 1; > 0: the passes also go on until every joint's
                                         //    mismatch is below this fraction of its accelerations
                                         //    (joint_forces.h); 0 = off (the paper's absolute eps)
  int max_passes = 0;                    // passes per step; 0 = 5 n^2 (the original's cap)
  bool centripetal = false;              // add w x (w x r) to joint-point accelerations (eq. 2 omits it)
  bool gyroscopic = true;                // the -w x I w term of eq. 1
  double control_k = 10.0;               // N/m, default stiffness of control-point springs
  SpringLaw control_spring = SpringLaw::kLinear;  // default law of control-point springs
  double control_cap = 1.0;              // rig units, cap c of capped springs (original: 1)
  double torsion_k = 10.0;               // N m/rad, joint-limit torsion springs
  SpringLaw torsion_spring = SpringLaw::kLinear;
  double torsion_cap = 0.5;              // rad, cap of capped torsion springs
  double torsion_tolerance = 0.1;        // 1, fraction of the range inside each limit where the
                                         //    torsion spring engages
  Integration integration = Integration::kArticulated;
  Interpolation interpolation = Interpolation::kLinear;
  int interpolation_steps = 12;          // steps over which a target jump is spread
                                         // (original: 25% of its 50 iterations)
  double interpolation_fallback = 1e-3;  // rig units: polar falls back to linear this near the origin

  int passes_cap(int nbone) const { return max_passes > 0 ? max_passes : 5 * nbone * nbone; }
};

// A preset by name ("paper" or "original"); throws InputError naming `source` otherwise.
EngineParams preset_params(const std::string& name, const std::string& source = "");

// The preset used when a scene names none: the one that converges on the paper's own rig
// (see README "Presets" for the measurement behind this choice).
constexpr const char* kDefaultPreset = "original";

}  // namespace physik
