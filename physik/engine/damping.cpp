#include "physik/engine/damping.h"

#include "physik/engine/newton_euler.h"

namespace physik {

void apply_damping(const Rig& rig, const EngineParams& params, SimState& s) {
  const double c = step_damping(params, s);
  if (c == 0.0) return;
  for (int i = 0; i < rig.nbone; ++i) {
    for (const Vec3* p : {&s.frames.head_world[i], &s.frames.tail_world[i]}) {
      const Vec3 v = s.vel_world[i] + s.omega_world[i].cross(*p - s.com_world[i]);
      apply_force_at(s, i, -c * v, *p);
    }
  }
}

}  // namespace physik
