// The rigs and targets of ik_comparison: see ik_cases.h.
#include "experiments/ik_cases.h"

#include <cmath>
#include <random>

#include "experiments/common.h"
#include "physik/ik/ik_solver.h"
#include "physik/io/rig_io.h"
#include "physik/model/rig_generators.h"

namespace physik::experiments {

std::vector<RigCase> make_ik_rigs(const std::string& models_dir, bool without_chain50) {
  std::vector<RigCase> rigs;
  for (int n : {3, 10, 50}) {
    if (without_chain50 && n == 50) continue;
    RigCase rc;
    rc.rig = make_chain_rig(n);
    rc.name = "chain" + std::to_string(n);
    rc.bone = n - 1;
    rc.chain = true;
    rigs.push_back(rc);
  }
  RigCase pinhead;
  pinhead.rig = load_rig(models_dir + "/rigs/pinhead.json");
  pinhead.name = "pinhead";
  pinhead.bone = pinhead.rig.find_bone("hand.L");
  rigs.push_back(pinhead);
  for (RigCase& rc : rigs) rc.reach = chain_reach(rc.rig, {{rc.bone, 1.0, Vec3::Zero()}});
  return rigs;
}

Targets make_ik_targets(const RigCase& rc, int n_reach, int n_unreach, int n_cont) {
  std::mt19937 rng(20240607);
  Targets t;
  const Vec3 root = rc.rig.bone_rest_head_world[0];
  for (int k = 0; k < n_reach; ++k) {
    if (rc.chain) {
      const double r =
          0.95 * rc.reach * std::cbrt(std::uniform_real_distribution<double>(0, 1)(rng));
      t.reach.push_back(root + r * random_direction(rng));
    } else {
      t.reach.push_back(
          forward_kinematics(rc.rig, random_legal_pose(rc.rig, rng)).tail_world[rc.bone]);
    }
  }
  for (int k = 0; k < n_unreach; ++k) {
    const double r = rc.reach * std::uniform_real_distribution<double>(1.1, 2.0)(rng);
    t.unreach.push_back(root + r * random_direction(rng));
  }
  for (int k = 0; k < n_cont; ++k) t.moves.push_back(0.01 * rc.reach * random_direction(rng));
  return t;
}

}  // namespace physik::experiments
