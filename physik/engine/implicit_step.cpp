#include "physik/engine/implicit_step.h"

#include <algorithm>

#include "physik/engine/articulated_body.h"
#include "physik/engine/control_springs.h"
#include "physik/engine/implicit_pose_terms.h"
#include "physik/engine/integrate_joint_space.h"
#include "physik/engine/newton_euler.h"
#include "physik/engine/torsion_springs.h"

namespace physik {

namespace {

void element_tangents(const Scene& scene, bool full, SimState& s) {
  const EngineParams& p = scene.params;
  for (std::size_t c = 0; c < scene.control_points.size(); ++c) {
    const ControlPoint& cp = scene.control_points[c];
    const Vec3 a = point_on_bone(s.frames, cp.bone, cp.alpha);
    s.control_stiffness[c] = spring_step_stiffness(cp.spring_in(p), cp.k_in(p), cp.cap_in(p),
                                                   s.target_effective_world[c] - a);
  }
  const Rig& rig = scene.rig;
  for (int i = 0; i < rig.nbone; ++i) {
    const auto& limits = rig.bone_limit[i];
    s.torsion_torque_world[i].setZero();
    if (!has_torsion_spring(rig, i) || p.torsion_k == 0.0) {
      s.torsion_stiffness[i].setZero();
      s.torsion_block_world[i].setZero();  // torsion_block_world() reads it without the stiffness
      continue;
    }
    const Vec3 theta = rotation_vector(s.pose.bone_local_rotation[i]);
    s.torsion_stiffness[i] = torsion_step_stiffness_local(limits, theta, p);
    const Mat3 R = (torsion_parent_orient(rig, s.frames, i) * rig.bone_rest_orient_parent[i])
                       .toRotationMatrix();  // R_pr
    s.torsion_block_world[i] =
        R * torsion_step_block_local(s.torsion_stiffness[i], theta, p.torsion_torque) *
        R.transpose();
    if (full && !s.torsion_stiffness[i].isZero(0.0)) {
      // the torque the force stage applied, and its pose terms (implicit_pose_terms.h (5))
      const Vec3 tau_local = torsion_torque_local(limits, theta, p);
      const Vec3 tau_pr = p.torsion_torque == TorsionTorque::kGradient
                              ? Vec3(left_jacobian_inverse_transpose(theta) * tau_local)
                              : tau_local;
      s.torsion_torque_world[i] = R * tau_pr;
      const PoseTermSelection& use = s.pose_term_selection;
      if (use.forces) {
        s.torsion_block_world[i] +=
            torsion_pose_block(R, theta, tau_local, p.torsion_torque, s.torsion_torque_world[i]);
      }
      // torsion_pose_block's frame term, -[tau]x, taken back when not selected
      if (use.forces != use.torque_frame) {
        s.torsion_block_world[i] += (use.forces ? 1.0 : -1.0) * skew(s.torsion_torque_world[i]);
      }
    }
  }
}

}  // namespace

void element_tangents(const Scene& scene, SimState& s) {
  element_tangents(scene, scene.params.implicit_linearisation == ImplicitLinearisation::kFull, s);
}

Mat3 torsion_block_world(const Rig&, const SimState& s, int i) {
  return s.torsion_block_world[i];
}

void add_point_inertia(const Mat3& A, const Vec3& r, SpatialInertia& I) {
  const Mat3 RA = skew(r) * A;  // [r]x A
  I.A.noalias() += RA * skew(r).transpose();
  I.B += RA;
  I.C += A;
}

namespace {

// -Phi^T A Phi a0 into the body's bias force: the element force's velocity-product share
inline void add_point_bias(const Mat3& A, const Vec3& r, const Vec6& a0, Vec6& bias) {
  const Vec3 f = A * (a0.tail<3>() + a0.head<3>().cross(r));  // A times the point's a0
  bias.head<3>() -= r.cross(f);
  bias.tail<3>() -= f;
}

// the velocity of bone b's material point at p (rig units/s)
inline Vec3 point_velocity(const SimState& s, int b, const Vec3& p) {
  return s.vel_world[b] + s.omega_world[b].cross(p - s.com_world[b]);
}

// the contacts' share of -h K v: K times the relative velocity of a's point to b's (b, when a
// bone, moving on at its start-of-step velocity: contacts.h), on a, and its opposite on b
void add_contact_rate_forces(double h, SimState& s) {
  for (const ContactElement& e : s.contact_elements) {
    Vec3 v = point_velocity(s, e.bone, e.point_world);
    if (e.other_bone >= 0) v -= point_velocity(s, e.other_bone, e.point_world);
    const Vec3 f = -h * (e.stiffness * v);
    apply_force_at(s, e.bone, f, e.point_world);
    if (e.other_bone >= 0) apply_force_at(s, e.other_bone, -f, e.point_world);
  }
}

// the stiffness' share of the step on the right-hand side: -h K v per element
void add_stiffness_rate_forces(const Scene& scene, double h, SimState& s) {
  add_contact_rate_forces(h, s);
  for (std::size_t c = 0; c < scene.control_points.size(); ++c) {
    const ControlPoint& cp = scene.control_points[c];
    const Vec3 a = point_on_bone(s.frames, cp.bone, cp.alpha);
    const Vec3 v = s.vel_world[cp.bone] + s.omega_world[cp.bone].cross(a - s.com_world[cp.bone]);
    apply_force_at(s, cp.bone, -h * (s.control_stiffness[c] * v), a);
  }
  const Rig& rig = scene.rig;
  for (int i = 0; i < rig.nbone; ++i) {
    if (s.torsion_stiffness[i].isZero(0.0)) continue;
    const int p = rig.bone_parent[i];
    const Vec3 w_rel = p < 0 ? s.omega_world[i] : Vec3(s.omega_world[i] - s.omega_world[p]);
    const Vec3 tau = -h * (torsion_block_world(rig, s, i) * w_rel);
    s.torque_world[i] += tau;
    if (p >= 0) s.torque_world[p] -= tau;
  }
}

// a0_i = X a0_p + c_i (root: c_0): the spatial accelerations when qacc = 0
void velocity_product_accels(const Rig& rig, const ArticulatedBodyData& d, std::vector<Vec6>& a0) {
  if (rig.nbone == 0) return;
  a0[0] = d.bias_accel[0];
  for (int i = 1; i < rig.nbone; ++i) {
    const int p = rig.bone_joint_parent[i];
    const Vec6& ap = a0[p];
    const Vec3 r = d.point_world[i] - d.point_world[p];
    a0[i].head<3>() = ap.head<3>() + d.bias_accel[i].head<3>();
    a0[i].tail<3>() = ap.tail<3>() - r.cross(ap.head<3>()) + d.bias_accel[i].tail<3>();
  }
}

// h D + h^2 K of the body elements into the articulated inertias and bias forces
void augment_bodies(const Scene& scene, double h, double c, SimState& s) {
  const Rig& rig = scene.rig;
  ArticulatedBodyData& d = s.articulated;
  // h D of the factor / I_com: the damper (1 - f) / dt I_com times h (1 - f at h = dt)
  const double rot = (1.0 - scene.params.angular_velocity_factor) * (h / scene.params.dt);
  const Mat3 damper = h * c * Mat3::Identity();
  for (int i = 0; i < rig.nbone; ++i) {
    const Vec3& o = d.point_world[i];
    const Vec6& a0 = s.accel_bias[i];
    SpatialInertia& I = d.inertia_art[i];
    Vec6& bias = d.bias_force[i];
    if (rot != 0.0) {
      const Mat3 Ir = rot * d.inertia_com_world[i];
      I.A += Ir;
      bias.head<3>() -= Ir * a0.head<3>();
    }
    if (c != 0.0) {
      for (const Vec3* p : {&s.frames.head_world[i], &s.frames.tail_world[i]}) {
        add_point_inertia(damper, *p - o, I);
        add_point_bias(damper, *p - o, a0, bias);
      }
    }
  }
  for (std::size_t k = 0; k < scene.control_points.size(); ++k) {
    const ControlPoint& cp = scene.control_points[k];
    const Mat3 A = h * h * s.control_stiffness[k];
    const Vec3 r = point_on_bone(s.frames, cp.bone, cp.alpha) - d.point_world[cp.bone];
    add_point_inertia(A, r, d.inertia_art[cp.bone]);
    add_point_bias(A, r, s.accel_bias[cp.bone], d.bias_force[cp.bone]);
  }
}

// h^2 K + h D of every contact on each bone it touches: the ground's exactly; a self-contact's
// (D = 0: its damper and friction are explicit) twice on each of its two bones, without its
// coupling block (contacts.h: backward Euler on the pair's relative motion with an effective mass
// at least the true one)
void augment_contacts(double h, SimState& s) {
  ArticulatedBodyData& d = s.articulated;
  for (const ContactElement& e : s.contact_elements) {
    const double share = e.other_bone >= 0 ? 2.0 : 1.0;
    const Mat3 A = share * (h * h * e.stiffness + h * e.damping);
    for (const int b : {e.bone, e.other_bone}) {
      if (b < 0) continue;
      const Vec3 r = e.point_world - d.point_world[b];
      add_point_inertia(A, r, d.inertia_art[b]);
      add_point_bias(A, r, s.accel_bias[b], d.bias_force[b]);
    }
  }
}

// h^2 K_j of the torsion springs as joint blocks
void joint_blocks(const Rig& rig, double h, SimState& s) {
  ArticulatedBodyData& d = s.articulated;
  d.joint_blocks = false;
  for (int i = 0; i < rig.nbone; ++i) {
    if (s.torsion_stiffness[i].isZero(0.0)) {
      d.joint_block[i].setZero();
      continue;
    }
    d.joint_block[i] = h * h * torsion_block_world(rig, s, i);
    d.joint_blocks = true;
  }
}

}  // namespace

JointSolveStats solve_implicit(const Scene& scene, SimState& s) {
  return solve_implicit(scene, s, scene.params.dt);
}

namespace {

// one linearised step of h with or without the pose terms; the forces are the step's input
void linearised_step(const Scene& scene, SimState& s, double h, bool full) {
  const Rig& rig = scene.rig;
  const EngineParams& p = scene.params;
  ArticulatedBodyData& d = s.articulated;
  element_tangents(scene, full, s);
  add_stiffness_rate_forces(scene, h, s);  // tau - h K v
  articulated_velocity_pass(rig, s, d);    // rigid inertias, bias forces
  velocity_product_accels(rig, d, s.accel_bias);
  if (full) rest_accelerations(scene, s);           // a0 and W, for the pose terms
  augment_bodies(scene, h, step_damping(p, s), s);  // + h D + h^2 K of body elements
  augment_contacts(h, s);                           // + h D + h^2 K of the contacts
  d.pose_terms = false;
  if (full) add_pose_terms(scene, h, s);  // + h^2 K's pose terms
  joint_blocks(rig, h, s);                // + h^2 K of joint elements
  articulated_backward_pass(rig, d);
  articulated_forward_pass(rig, s, d);
}

}  // namespace

JointSolveStats solve_implicit(const Scene& scene, SimState& s, double h) {
  const Rig& rig = scene.rig;
  const EngineParams& p = scene.params;
  ArticulatedBodyData& d = s.articulated;
  d.torque_per_omega = (p.angular_velocity_factor - 1.0) / p.dt;  // the explicit factor torque
  d.cancel_gyroscopic = !p.gyroscopic;

  const bool full = p.implicit_linearisation == ImplicitLinearisation::kFull;
  if (full && s.pose_term_selection.gauss_newton_retake) {  // kept for a Gauss-Newton retake
    std::copy(s.force_world.begin(), s.force_world.end(), s.step_force_world.begin());
    std::copy(s.torque_world.begin(), s.torque_world.end(), s.step_torque_world.begin());
  }
  linearised_step(scene, s, h, full);
  if (full && s.pose_term_selection.gauss_newton_retake && !d.pose_terms_positive) {
    // a pivot's symmetric part is not positive definite with the pose terms: the step is taken
    // again with the Gauss-Newton system, whose pivots' are (implicit_step.h)
    std::copy(s.step_force_world.begin(), s.step_force_world.end(), s.force_world.begin());
    std::copy(s.step_torque_world.begin(), s.step_torque_world.end(), s.torque_world.begin());
    linearised_step(scene, s, h, false);
    ++s.implicit_gauss_newton_steps;
  }
  articulated_joint_forces(rig, s);

  JointSolveStats stats;
  stats.passes = 1;  // one sweep of the recursion, no iteration
  stats.mismatch = 0.0;
  return stats;
}

}  // namespace physik
