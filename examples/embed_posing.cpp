// Drag a hand in a circle, three PhysIK steps per frame, then solve the last pose.
#include <cmath>
#include <cstdio>

#include "physik/io/scene_io.h"
#include "physik/posing/posing_session.h"

int main(int argc, char** argv) {
  const char* path = argc > 1 ? argv[1] : "models/scenes/pinhead_two_hands.json";
  physik::PosingSession session(physik::load_scene(path));  // allocates, once
  const physik::Vec3 centre = session.state().target_goal_world[0];
  for (int frame = 0; frame < 120; ++frame) {  // the tool's frame loop: nothing allocated
    const double a = 0.05 * frame / 0.3;       // 0.05 rig units per frame on a 0.3 circle
    session.set_target(0, centre + 0.3 * physik::Vec3(std::cos(a) - 1.0, 0.0, std::sin(a)));
    session.advance(3);
    std::printf("frame %d lag %.4f\n", frame, session.residual());
  }
  const physik::SolveResult r = session.solve();  // the rest pose: the equilibrium solve
  std::printf("solve: %s in %d iterations, residual %.2e\n",
              r.converged ? "converged" : "not converged", r.steps, r.residual);
  return r.converged ? 0 : 1;
}
