// The implicit step's pose terms (implicit_pose_terms.h gives the derivation).
#include "physik/engine/implicit_pose_terms.h"

#include <cmath>

#include "physik/engine/articulated_body.h"
#include "physik/engine/forces.h"

namespace physik {

namespace {

// a force vector (n; f) about o_child moved to o_parent, r = o_child - o_parent
inline Vec6 shift_force(const Vec6& w, const Vec3& r) {
  Vec6 out;
  out << w.head<3>() + r.cross(w.tail<3>()), w.tail<3>();
  return out;
}

// a motion vector (w; v) about o_parent seen at o_child, r = o_child - o_parent
inline Vec6 shift_motion(const Vec6& m, const Vec3& r) {
  Vec6 out;
  out << m.head<3>(), m.tail<3>() - r.cross(m.head<3>());
  return out;
}

// the rigid inertia of body i about its point o_i times a motion vector
inline Vec6 rigid_times(const Rig& rig, const ArticulatedBodyData& d, const SimState& s, int i,
                        const Vec6& m) {
  const double mass = rig.bone_mass[i];
  const Vec3 e = s.com_world[i] - d.point_world[i];
  // I = [I_c + m [e]x [e]x^T, m [e]x; m [e]x^T, m]: the centre's momentum and its moment
  const Vec3 lin = mass * (m.tail<3>() + m.head<3>().cross(e));  // m (v + w x e)
  Vec6 out;
  out << d.inertia_com_world[i] * m.head<3>() + e.cross(lin), lin;
  return out;
}

// body i's velocity twist about o_i: (w; velocity of the body point at o_i)
inline Vec6 body_twist(const ArticulatedBodyData& d, const SimState& s, int i) {
  const Vec3& w = s.omega_world[i];
  Vec6 out;
  out << w, s.vel_world[i] - w.cross(s.com_world[i] - d.point_world[i]);
  return out;
}

// h^2 [dA dB; dE 0] into body i's augmented inertia, and its share of the right-hand side:
// the bias force gets [dA dB; dE 0] (h V_i - h^2 a0_i) (the -h K v force, and the velocity
// products' part the augmented inertia multiplies: implicit_step.h)
inline void add_body_stiffness(double h, const Mat3& dA, const Mat3& dB, const Mat3& dE,
                               const Vec6& y, int i, ArticulatedBodyData& d) {
  d.inertia_art[i].A += h * h * dA;
  d.inertia_art[i].B += h * h * dB;
  d.inertia_lower[i] += h * h * dE;
  d.bias_force[i].head<3>() += dA * y.head<3>() + dB * y.tail<3>();
  d.bias_force[i].tail<3>() += dE * y.head<3>();
}

// The world-held wrenches about each o_b (rest_wrench: the pose forces' points and couples,
// implicit_pose_terms.h W's F_b)
class RestWrenches final : public PoseForces {
 public:
  RestWrenches(const ArticulatedBodyData& d, std::vector<Vec6>& w) : d_(d), w_(w) {}
  void point(int b, const Vec3& at, const Vec3& f) override {
    const Vec3 arm = at - d_.point_world[b];
    w_[b].head<3>() += arm.cross(f);
    w_[b].tail<3>() += f;
  }
  void couple(int b, const Vec3& tau) override { w_[b].head<3>() += tau; }

 private:
  const ArticulatedBodyData& d_;
  std::vector<Vec6>& w_;
};

// the joints' torques, on the child and minus on the parent, into per-body wrenches `w` times
// `sign`: the rest solve's bias force (sign -1, the ABA's bias is minus the external wrench) or
// the sketch's transmitted wrench (sign +1)
class JointTorques final : public PoseForces {
 public:
  JointTorques(const Rig& rig, double sign, std::vector<Vec6>& w) : rig_(rig), sign_(sign), w_(w) {}
  void joint(int i, const Vec3& t) override {
    w_[i].head<3>() += sign_ * t;
    w_[rig_.bone_parent[i]].head<3>() -= sign_ * t;
  }

 private:
  const Rig& rig_;
  double sign_;
  std::vector<Vec6>& w_;
};

// (2): each point force's point moving under its held force, -G_p = [[-[f]x[r]x, [f]x]; 0] (a
// couple held in the world does not move with its body: no term)
class PointsMoving final : public PoseForces {
 public:
  PointsMoving(double h, SimState& s) : h_(h), s_(s) {}
  void point(int b, const Vec3& at, const Vec3& f) override {
    ArticulatedBodyData& d = s_.joint_space.articulated;
    const Vec3 r = at - d.point_world[b];
    const Mat3 F = skew(f);
    const Vec6 y = h_ * body_twist(d, s_, b) - h_ * h_ * s_.implicit.accel_bias[b];
    add_body_stiffness(h_, -F * skew(r), F, Mat3::Zero(), y, b, d);
  }

 private:
  double h_;
  SimState& s_;
};

// (3) and the d'Alembert wrenches: H(I_b a0_b) = [[-[n]x, -[g]x]; [-[g]x, 0]] per body (with
// `turn`), and rest_wrench_b <- F_b - I_b a0_b (with `wrench`)
void add_inertia_turn(const Rig& rig, double h, bool wrench, bool turn, SimState& s) {
  ImplicitWorkspace& im = s.implicit;
  ArticulatedBodyData& d = s.joint_space.articulated;
  const ArticulatedBodyData& r = im.articulated_rest;
  for (int i = 0; i < rig.nbone; ++i) {
    const Vec6 w = rigid_times(rig, d, s, i, r.accel_spatial[i]);
    if (wrench) im.rest_wrench[i] -= w;
    if (!turn) continue;
    const Mat3 N = skew(w.head<3>()), G = skew(w.tail<3>());
    const Vec6 y = h * body_twist(d, s, i) - h * h * im.accel_bias[i];
    add_body_stiffness(h, -N, -G, -G, y, i, d);
  }
}

// (1) on a universal joint j (joint_coordinates.h): its first axis s0 is fixed in the parent, so
// its own second coordinate does not turn it, while the row G_j a_j counts every own column as a
// ball's (whose three axes all turn with the bone). Taken back: the entry g01 = s0^T G_A s1 from
// its pivot (a joint block -s0 g01 s1^T, which S^T . S turns into the (0, 1) entry alone), and
// its rate's share from the right-hand side (G_j's -h V_j / h^2 part along s1: +s0 g01 t1' / h)
void first_axis_holds(SimState& s, double h, int j) {
  ArticulatedBodyData& d = s.joint_space.articulated;
  const Vec3& s0 = d.axis0_world[j];
  const Vec3& s1 = d.axis1_world[j];
  const double g01 = s0.dot(d.row_ang[j] * s1);
  d.joint_block[j].noalias() -= (g01 * s0) * s1.transpose();
  d.joint_blocks = true;
  d.joint_torque[j] += s0 * (g01 * s.joint_space.joint_vel_local[j][1] / h);
}

// (1): W_j, the subtree's wrench, leaves to root; joint j's row G_j = h^2 [-[n]x, -[g]x] (the
// top rows of H(W_j) about o_j) and its right-hand side G_j (h^2 a0_j - h V_j) / h^2
void add_turning_axes(const Rig& rig, double h, SimState& s) {
  ImplicitWorkspace& im = s.implicit;
  ArticulatedBodyData& d = s.joint_space.articulated;
  for (int i = rig.nbone - 1; i > 0; --i) {
    const int p = rig.bone_parent[i];
    im.rest_wrench[p] += shift_force(im.rest_wrench[i], d.point_world[i] - d.point_world[p]);
  }
  // the root: its rotation rows only (its translation columns do not turn); with the d'Alembert
  // wrenches in, the whole tree's W_0 vanishes (a free root), up to round-off
  for (int j = 0; j < rig.nbone; ++j) {
    const Vec3 n = im.rest_wrench[j].head<3>(), g = im.rest_wrench[j].tail<3>();
    d.row_ang[j] = -h * h * skew(n);
    d.row_lin[j] = -h * h * skew(g);
    const Vec6 y = h * h * im.accel_bias[j] - h * body_twist(d, s, j);
    d.joint_torque[j] = -n.cross(y.head<3>()) - g.cross(y.tail<3>());
    if (rig.bone_joint_type[j] == JointType::kUniversal) first_axis_holds(s, h, j);
  }
}

// (4): I^Z = h^2 I_b (rigid), T_i from the parent's rest acceleration at o_i, and the rate
// z(v) = sum A0_p(i) x S_i v_i, root to leaves, whose force -h I_b z_b(v) joins the bias
void add_turning_accelerations(const Rig& rig, double h, SimState& s) {
  ImplicitWorkspace& im = s.implicit;
  ArticulatedBodyData& d = s.joint_space.articulated;
  const ArticulatedBodyData& r = im.articulated_rest;
  for (int i = 0; i < rig.nbone; ++i) {
    const double m = rig.bone_mass[i];
    const Vec3 e = s.com_world[i] - d.point_world[i];
    SpatialInertia& Z = d.inertia_z[i];
    Z.A = h * h * d.inertia_com_world[i];
    Z.A.noalias() += (h * h * m) * (e.squaredNorm() * Mat3::Identity() - e * e.transpose());
    Z.B = (h * h * m) * skew(e);
    Z.C = (h * h * m) * Mat3::Identity();
    d.inertia_z_lower[i] = Z.B.transpose();
    const int p = rig.bone_parent[i];
    if (p < 0) {
      d.z_accel[i] << Vec3::Zero(), r.accel_spatial[i].tail<3>();  // the root's (0; a_com)
      im.pose_rate[i] << Vec3::Zero(), d.z_accel[i].tail<3>().cross(s.omega_world[i]);
    } else {
      const Vec3 rr = d.point_world[i] - d.point_world[p];
      d.z_accel[i] = shift_motion(r.accel_spatial[p], rr);
      const Vec3 w_rel = s.omega_world[i] - s.omega_world[p];
      im.pose_rate[i] = shift_motion(im.pose_rate[p], rr);
      im.pose_rate[i].head<3>() += d.z_accel[i].head<3>().cross(w_rel);
      im.pose_rate[i].tail<3>() += d.z_accel[i].tail<3>().cross(w_rel);
      // a universal joint's second axis turns after its first hinge's rest acceleration
      // s0 t0''_rest: its T's angular block gains (t0''_rest s0 x s1) s1^T
      d.z_axis_turn[i].setZero();
      if (rig.bone_joint_type[i] == JointType::kUniversal) {
        d.z_axis_turn[i] = r.joint_accel_local[i][0] * d.axis0_world[i].cross(d.axis1_world[i]);
        im.pose_rate[i].head<3>() += d.z_axis_turn[i] * d.axis1_world[i].dot(w_rel);
      }
    }
    d.bias_force[i] += h * rigid_times(rig, d, s, i, im.pose_rate[i]);
  }
}

}  // namespace

void rest_accelerations(const Scene& scene, const PoseTermSelection& terms, SimState& s) {
  ImplicitWorkspace& im = s.implicit;
  const Rig& rig = scene.rig;
  const ArticulatedBodyData& d = s.joint_space.articulated;
  ArticulatedBodyData& r = im.articulated_rest;
  for (int i = 0; i < rig.nbone; ++i) {
    r.inertia_art[i] = d.inertia_art[i];
    r.point_world[i] = d.point_world[i];
    r.axis0_world[i] = d.axis0_world[i];  // a hinge's or universal's axes (joint_coordinates.h)
    r.axis1_world[i] = d.axis1_world[i];
    im.rest_wrench[i].setZero();
  }
  RestWrenches world_held(d, im.rest_wrench);
  pose_forces(scene, s, world_held);
  if (!terms.needs_rest()) return;  // a0 is not needed
  // the ABA's bias force is minus the external wrench; the joints' torques join it here but not
  // rest_wrench, which holds the world-held forces only (implicit_pose_terms.h, (1) and (5))
  for (int i = 0; i < rig.nbone; ++i) r.bias_force[i] = -im.rest_wrench[i];
  JointTorques on_bias(rig, -1.0, r.bias_force);
  pose_forces(scene, s, on_bias);
  articulated_backward_pass(rig, r);
  articulated_forward_pass(rig, body_motion(s), r);
}

void add_pose_terms(const Scene& scene, const ImplicitStage& stage, SimState& s) {
  ImplicitWorkspace& im = s.implicit;
  const double h = stage.h;
  const Rig& rig = scene.rig;
  ArticulatedBodyData& d = s.joint_space.articulated;
  const PoseTermSelection& use = stage.terms;
  for (int i = 0; i < rig.nbone; ++i) d.inertia_lower[i] = d.inertia_art[i].B.transpose();
  if (use.forces) {
    PointsMoving moving(h, s);
    pose_forces(scene, s, moving);
  } else {
    for (Vec6& w : im.rest_wrench) w.setZero();  // (1) without the forces' share
  }
  if (use.inertia_wrench || use.inertia_turn) {
    add_inertia_turn(rig, h, use.inertia_wrench, use.inertia_turn, s);
  }
  if (use.torsion_in_wrench) {  // the joints' torques in the transmitted wrench
    JointTorques in_wrench(rig, 1.0, im.rest_wrench);
    pose_forces(scene, s, in_wrench);
  }
  add_turning_axes(rig, h, s);
  if (use.turning_accelerations) {
    add_turning_accelerations(rig, h, s);
  } else {
    for (int i = 0; i < rig.nbone; ++i) {  // no I^Z: the pass's z stays 0
      d.inertia_z[i] = SpatialInertia{};
      d.inertia_z_lower[i].setZero();
      d.z_accel[i].setZero();
      d.z_axis_turn[i].setZero();
    }
  }
  d.pose_terms = true;
}

}  // namespace physik
