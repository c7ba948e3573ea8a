// The Verlet mass-spring chain used as an IK solver: mass-weighted length constraints, goals
// pinned like infinitely heavy nodes, optional gravity.
//
// Source: the IK guide (seed 001), "Mass Spring Solver" (position-based, after Jakobsen's
// "Advanced character physics"): no Hooke's law, because stable stiffness depends on dt.
// World frame, rig units, s, kg.
//
// Nodes: the root's head (the anchor, infinite mass) and the tail of every active bone, with the
// lumped rod mass m_node = m_i / 2 + sum over children c of m_c / 2 (kg); the tail of a bone the
// world holds (a fixed root's body, ik_solver.h held_by_world) is an anchor too.
// Per iteration (one Verlet frame):
//   Verlet:   x_new = x + k_v (x - x_prev) + g dt^2          (k_v = velocity_keep, a damping;
//             the guide writes 0.5 g dt^2 into its prev buffer; plain Verlet is g dt^2)
//   passes:   repeat constraint_passes times
//     goals:  a point y = (1 - alpha) x_h + alpha x_t on a bone is moved onto its target t by
//             distributing d = t - y over the two ends with inverse-mass weights w = 1/m:
//               x_h += (1 - alpha) w_h s d,  x_t += alpha w_t s d,
//               s = 1 / ((1 - alpha)^2 w_h + alpha^2 w_t)          (w = 0 at the anchor)
//     lengths (guide's mass-weighted centre; erratum: the guide divides by m_a m_b and writes
//             both results into the same node -- the weighted centre needs m_a + m_b):
//               c = (m_a x_a + m_b x_b) / (m_a + m_b)
//               x_a = c + normalize(x_a - c) L m_b / (m_a + m_b)
//               x_b = c + normalize(x_b - c) L m_a / (m_a + m_b)
//             so the heavier node moves less; at the anchor only the free end moves. The sweep
//             alternates root-to-leaves and leaves-to-root between passes, so a correction
//             crosses the chain in two passes (one direction only: a 10-bone chain needed ~15x
//             more iterations and stalled on 16% of targets).
//   rotations: as FABRIK, in local space: each active bone aims at its node (aim_bones_at), with
//             limit clamping; the nodes are then reset to the FK tails (so the velocity carries
//             that correction into the next frame).
#include <cmath>

#include "physik/ik/ik_solver.h"

namespace physik {

void mass_weighted_length(Vec3& xa, Vec3& xb, double ma, double mb, double L) {
  const Vec3 c = (ma * xa + mb * xb) / (ma + mb);
  const Vec3 da = xa - c, db = xb - c;
  if (da.norm() < 1e-12 || db.norm() < 1e-12) return;  // coincident: no direction to keep
  xa = c + da.normalized() * (L * mb / (ma + mb));
  xb = c + db.normalized() * (L * ma / (ma + mb));
}

namespace {

// one projection pass: every goal pulls its attachment (mass-weighted between the bone's head and
// tail nodes), then every bone's length is restored, sweeping root to leaves on even passes and
// leaves to root on odd ones (so a correction travels the whole chain in two passes, not one bone
// per pass)
void project(const IkProblem& pb, const std::vector<double>& node_mass, const Vec3& anchor,
             int pass, std::vector<Vec3>& x) {
  const Rig& rig = *pb.rig;
  const int n = rig.nbone;
  for (const IkGoal& g : pb.goals) {
    const int b = g.bone;
    if (!pb.active[b]) continue;  // held by the world (a fixed root's body): nothing moves
    // the head's node moves unless it is the anchor or the tail of a bone the world holds
    const bool head_free = rig.bone_parent[b] >= 0 && pb.active[rig.bone_parent[b]];
    const double wh = head_free ? 1.0 / node_mass[rig.bone_parent[b]] : 0.0;
    const double wt = 1.0 / node_mass[b];
    const double a = g.alpha;
    const double den = (1 - a) * (1 - a) * wh + a * a * wt;
    if (den <= 0.0) continue;
    Vec3 head = head_free ? x[rig.bone_parent[b]] : anchor;
    const Vec3 d = g.target_world - ((1 - a) * head + a * x[b]);
    const double s = 1.0 / den;
    if (head_free) x[rig.bone_parent[b]] += (1 - a) * wh * s * d;
    x[b] += a * wt * s * d;
  }
  for (int s = 0; s < n; ++s) {
    const int i = pass % 2 == 0 ? s : n - 1 - s;
    if (!pb.active[i]) continue;
    const double L = rig.bone_length[i];
    const int par = rig.bone_parent[i];
    if (par < 0 || !pb.active[par]) {  // its head fixed: the anchor, or a held bone's tail
      const Vec3 head = par < 0 ? anchor : x[par];
      const Vec3 d = x[i] - head;
      if (d.norm() > 1e-12) x[i] = head + d.normalized() * L;
      continue;
    }
    mass_weighted_length(x[par], x[i], node_mass[par], node_mass[i], L);
  }
}

}  // namespace

IkReport solve_mass_spring(const IkProblem& pb, Pose& pose) {
  const Rig& rig = *pb.rig;
  const IkOptions& opt = pb.options;
  const int n = rig.nbone;
  std::vector<double> node_mass(n, 0.0);  // kg, tail node of bone i
  for (int i = 0; i < n; ++i) {
    node_mass[i] += 0.5 * rig.bone_mass[i];
    if (rig.bone_parent[i] >= 0) node_mass[rig.bone_parent[i]] += 0.5 * rig.bone_mass[i];
  }
  std::vector<Vec3> x(n), x_prev(n);
  bool started = false;
  const Vec3 gdt2 = opt.gravity_world * opt.dt * opt.dt;

  auto iterate = [&](Pose& p, BoneFrames& f) {
    const Vec3 anchor = p.root_head_world;  // never moved
    if (!started) {
      for (int i = 0; i < n; ++i) x[i] = x_prev[i] = f.tail_world[i];
      started = true;
    }
    for (int i = 0; i < n; ++i) {  // Verlet: the velocity kept, and gravity
      if (!pb.active[i]) continue;
      const Vec3 v = opt.velocity_keep * (x[i] - x_prev[i]);
      x_prev[i] = x[i];
      x[i] += v + gdt2;
    }
    for (int pass = 0; pass < opt.constraint_passes; ++pass)
      project(pb, node_mass, anchor, pass, x);
    aim_bones_at(rig, pb.active, x, opt.respect_limits, p, f);
    for (int i = 0; i < n; ++i) {
      if (pb.active[i]) x[i] = f.tail_world[i];
    }
  };
  return run_ik_loop("mass-spring", pb, pose, iterate);
}

}  // namespace physik
