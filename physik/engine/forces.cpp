#include "physik/engine/forces.h"

#include "physik/engine/contacts.h"
#include "physik/engine/control_springs.h"
#include "physik/engine/damping.h"
#include "physik/engine/newton_euler.h"
#include "physik/engine/torsion_springs.h"

namespace physik {

void apply_forces(const Scene& scene, SimState& s, const ForceSelection& selection) {
  const Rig& rig = scene.rig;
  const EngineParams& p = scene.params;
  // torsion reads s.pose, which init_state and the end of every step keep in sync with frames
  prepare_bodies(rig, p, s);
  apply_damping(rig, p, s);
  apply_control_springs(scene, s);
  if (selection.torsion_springs) apply_torsion_springs(rig, p, s);
  if (selection.gravity) apply_gravity(scene, s);
  if (selection.contacts) apply_contacts(scene, s, selection.step > 0.0 ? selection.step : p.dt);
}

}  // namespace physik
