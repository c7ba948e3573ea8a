#include "reference/mujoco_runner.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include "physik/engine/forces.h"
#include "physik/engine/interpolation.h"
#include "physik/engine/newton_euler.h"
#include "physik/engine/run_monitor.h"
#include "physik/model/joint_angles.h"
#include "physik/model/joint_coordinates.h"
#include "physik/model/message_number.h"

namespace physik {

const char* to_string(ReferenceMode mode) {
  return mode == ReferenceMode::kSameForces ? "same-forces" : "exact-constraints";
}

namespace {

Vec3 vec_at(const mjtNum* p) {
  return Vec3(p[0], p[1], p[2]);
}

void put(mjtNum* p, const Vec3& v) {
  p[0] = v.x();
  p[1] = v.y();
  p[2] = v.z();
}

}  // namespace

MjcfBodyMap::MjcfBodyMap(const Rig& rig, const mjModel* m)
    : body(rig.nbone, -1), offset(rig.nbone), single(rig.nbone, 1) {
  const std::vector<std::string> names = mjcf_bone_names(rig);
  for (int i = 0; i < rig.nbone; ++i) {
    const int lead = rig.bone_body[i];
    if (lead == i) {
      body[i] = mj_name2id(m, mjOBJ_BODY, names[i].c_str());
      if (body[i] < 0) {
        throw std::runtime_error("MuJoCo: no body named '" + names[i] + "' in the rig's model");
      }
    } else {
      body[i] = body[lead];
      offset[i] = mjcf_body_offset(rig, i);
      single[i] = 0;
      single[lead] = 0;
    }
  }
}

void set_mujoco_state(const Rig& rig, const SimState& s, const mjModel* m, mjData* d) {
  set_mujoco_state(rig, s, m, d, MjcfBodyMap(rig, m));
}

namespace {

// the angles and rates of a body's hinges (joints j0 .. j0 + count - 1, each about a local axis,
// in order) from bone i's local rotation q and relative angular velocity w_rel (world): the
// angles of L^-1 q in the hinges' order (joint_coordinates.h), the rates the solution of
// S^T S t' = S^T w_rel on the hinges' world axes s_k = R_p R_rest L R_1 .. R_{k-1} a_k
void set_hinges(const Rig& rig, const SimState& s, int i, const mjModel* m, mjData* d, int j0,
                int count) {
  int axis[3] = {0, 0, 0};
  for (int k = 0; k < count; ++k) {
    const Vec3 a = vec_at(m->jnt_axis + 3 * (j0 + k));
    a.cwiseAbs().maxCoeff(&axis[k]);
  }
  const Quat L = mjcf_joint_offset(rig, i, JointModel::kRigJoints);
  const Quat q = (L.conjugate() * s.pose.bone_local_rotation[i]).normalized();
  Vec3 t = Vec3::Zero();
  if (count == 1) {
    const Quat h = q.w() < 0.0 ? Quat(-q.w(), -q.x(), -q.y(), -q.z()) : q;
    t[0] = 2.0 * std::atan2(h.vec()[axis[0]], h.w());
  } else {
    const int third = count == 3 ? axis[2] : 3 - axis[0] - axis[1];
    t = intrinsic_euler(q.toRotationMatrix(), axis[0], axis[1], third);
  }
  const int p = rig.bone_parent[i];
  const Quat parent = p < 0 ? Quat::Identity() : s.frames.orient_world[p];
  Quat frame = parent * rig.bone_rest_orient_parent[i] * L;
  Eigen::Matrix<double, 3, Eigen::Dynamic> S(3, count);
  for (int k = 0; k < count; ++k) {
    S.col(k) = frame * Vec3::Unit(axis[k]);
    frame = frame * Quat(Eigen::AngleAxisd(t[k], Vec3::Unit(axis[k])));
  }
  const Vec3 w_rel = s.omega_world[i] - (p < 0 ? Vec3::Zero() : s.omega_world[p]);
  const Eigen::VectorXd rate = (S.transpose() * S).ldlt().solve(S.transpose() * w_rel);
  for (int k = 0; k < count; ++k) {
    d->qpos[m->jnt_qposadr[j0 + k]] = t[k];
    d->qvel[m->jnt_dofadr[j0 + k]] = rate[k];
  }
}

}  // namespace

void set_mujoco_state(const Rig& rig, const SimState& s, const mjModel* m, mjData* d,
                      const MjcfBodyMap& bodies) {
  mj_resetData(m, d);
  for (int i = 0; i < rig.nbone; ++i) {
    if (rig.bone_weld[i] >= 0) continue;  // in its group's body, which has the group's joint
    const int b = bodies.body[i];
    const Quat& R = s.frames.orient_world[i];
    const int p = rig.bone_parent[i];
    // angular velocity relative to the parent, in the bone's own frame
    const Vec3 w_rel_local =
        R.conjugate() * (s.omega_world[i] - (p < 0 ? Vec3::Zero() : s.omega_world[p]));
    const int j0 = m->body_jntadr[b], jn = j0 + m->body_jntnum[b];
    if (jn > j0 && m->jnt_type[j0] == mjJNT_HINGE) {
      set_hinges(rig, s, i, m, d, j0, jn - j0);
      continue;
    }
    for (int j = j0; j < jn; ++j) {
      mjtNum* qpos = d->qpos + m->jnt_qposadr[j];
      mjtNum* qvel = d->qvel + m->jnt_dofadr[j];
      if (m->jnt_type[j] == mjJNT_FREE) {
        put(qpos, s.com_world[i]);
        qpos[3] = R.w(), qpos[4] = R.x(), qpos[5] = R.y(), qpos[6] = R.z();
        put(qvel, s.vel_world[i]);
        put(qvel + 3, R.conjugate() * s.omega_world[i]);
      } else if (m->jnt_type[j] == mjJNT_BALL) {
        const Quat q = s.pose.bone_local_rotation[i].normalized();  // a ball has no lock
        qpos[0] = q.w(), qpos[1] = q.x(), qpos[2] = q.y(), qpos[3] = q.z();
        put(qvel, w_rel_local);
      }
    }
  }
}

void read_mujoco_state(const Rig& rig, const mjModel* m, const mjData* d, SimState& s) {
  read_mujoco_state(rig, m, d, s, MjcfBodyMap(rig, m));
}

void read_mujoco_state(const Rig& rig, const mjModel* m, const mjData* d, SimState& s,
                       const MjcfBodyMap& bodies) {
  mjtNum vel6[6];
  for (int i = 0; i < rig.nbone; ++i) {
    const int b = bodies.body[i];
    const mjtNum* q = d->xquat + 4 * b;
    const Quat Rb = Quat(q[0], q[1], q[2], q[3]).normalized();
    const Vec3 xb = vec_at(d->xpos + 3 * b);
    // (rotation, translation) of the body's centre of mass xipos, world axes: the body frame's
    // origin for a body of one bone
    mj_objectVelocity(m, d, mjOBJ_BODY, b, vel6, 0);
    Quat R = Rb;
    Vec3 com = xb;
    Vec3 v = vec_at(vel6 + 3);
    const Vec3 w = vec_at(vel6);
    if (!bodies.single[i]) {  // a welded group's bone at its offset in the body
      const MjcfBodyOffset& o = bodies.offset[i];
      R = (Rb * o.quat).normalized();
      com = xb + Rb * o.pos;
      v += w.cross(Vec3(com - vec_at(d->xipos + 3 * b)));
    }
    const Vec3 half = R * Vec3(0, 0.5 * rig.bone_length[i], 0);
    s.frames.orient_world[i] = R;
    s.frames.head_world[i] = com - half;
    s.frames.tail_world[i] = com + half;
    s.com_world[i] = com;
    s.omega_world[i] = w;
    s.vel_world[i] = v;
  }
  local_rotations_from_world(rig, s.frames, s.pose);
}

MujocoReference::MujocoReference(const Scene& scene, ReferenceMode mode)
    : scene_(scene), mode_(mode), residuals_(scene.control_points.size()) {
  MjcfOptions o;
  o.joints = joint_model(mode, scene.params);
  o.dt = scene.params.dt;
  o.source = scene.rig_file;
  const MjcfOptions options = mjcf_contacts(scene, o);  // MuJoCo's own gravity and contacts
  m_ = rig_to_mjmodel(scene.rig, options);
  d_ = make_rig_mjdata(scene.rig, options, m_.get());
  bodies_ = std::make_unique<MjcfBodyMap>(scene.rig, m_.get());
  reset();
}

void MujocoReference::reset() {
  SimState s;
  init_state(scene_, s);  // PhysIK's initial state: pose, velocities, targets
  set_state(s);
}

void MujocoReference::set_state(const SimState& state) {
  s_ = state;
  set_mujoco_state(scene_.rig, s_, m_.get(), d_.get(), *bodies_);
  mj_step1(m_.get(), d_.get());
  read_mujoco_state(scene_.rig, m_.get(), d_.get(), s_, *bodies_);
}

bool MujocoReference::bad_acceleration() const {
  return d_->warning[mjWARN_BADQACC].number > 0 || d_->warning[mjWARN_BADQVEL].number > 0 ||
         d_->warning[mjWARN_BADQPOS].number > 0;
}

StepStats MujocoReference::step() {
  const Rig& rig = scene_.rig;
  const EngineParams& p = scene_.params;
  const mjModel* m = m_.get();
  mjData* d = d_.get();

  // PhysIK's own force stages on the PhysIK view of MuJoCo's state
  update_targets(scene_, s_);
  // the elements MuJoCo does not apply itself (forces.h: gravity and the contacts are its own,
  // and in exact-constraints mode its joint limits replace the torsion springs)
  ForceStage stage;
  stage.for_ = mode_ == ReferenceMode::kSameForces ? ForceStage::For::kMujocoSameForces
                                                   : ForceStage::For::kMujocoExactConstraints;
  apply_forces(scene_, s_, stage);

  // the angular-velocity factor as a torque, and the external forces into MuJoCo: each body's
  // at its centre of mass (xipos), its bones' forces and torques moved there
  const double torque_per_w = (p.angular_velocity_factor - 1.0) / p.dt;
  mju_zero(d->xfrc_applied, 6 * m->nbody);
  for (int i = 0; i < rig.nbone; ++i) {
    const Vec3& w = s_.omega_world[i];
    const Mat3 I = inertia_world(rig, s_.frames.orient_world[i], i);
    Vec3 torque = s_.torque_world[i] + I * (torque_per_w * w);
    // gyroscopic off: each rod's own w x I w about its centre (MuJoCo's body term is their sum
    // and the parallel axes' part, which the rods' centres' motion carries in PhysIK too)
    if (!p.gyroscopic) torque += w.cross(I * w);
    const int b = bodies_->body[i];
    if (bodies_->single[i]) {
      put(d->xfrc_applied + 6 * b, s_.force_world[i]);
      put(d->xfrc_applied + 6 * b + 3, torque);
      continue;
    }
    torque += Vec3(s_.com_world[i] - vec_at(d->xipos + 3 * b)).cross(s_.force_world[i]);
    mjtNum* f = d->xfrc_applied + 6 * b;
    for (int k = 0; k < 3; ++k) {
      f[k] += s_.force_world[i][k];
      f[3 + k] += torque[k];
    }
  }
  mj_step2(m, d);
  const int solver_iter = d->solver_iter;
  mj_step1(m, d);
  read_mujoco_state(rig, m, d, s_, *bodies_);
  s_.step += 1;
  s_.time += p.dt;

  StepStats st;
  st.passes = solver_iter;
  st.mismatch = 0.0;
  st.kinetic_energy = kinetic_energy(rig, s_);
  control_residuals(scene_, s_, residuals_);  // sized once in the constructor: no allocation
  for (double r : residuals_) st.max_residual = std::max(st.max_residual, r);
  st.joint_separation = max_joint_separation(rig, s_.frames);
  return st;
}

std::string mujoco_warning(const mjModel* m, const mjData* d) {
  const struct {
    int index;
    const char* name;
    std::string meaning;
  } kinds[] = {
      {mjWARN_CONTACTFULL, "mjWARN_CONTACTFULL",
       "its contact list (nconmax " + std::to_string(m->nconmax) + ") was full: contacts dropped"},
      {mjWARN_CNSTRFULL, "mjWARN_CNSTRFULL",
       "its constraint rows (njmax " + std::to_string(m->njmax) +
           ") were full: contacts or limits dropped"},
      {mjWARN_BADQACC, "mjWARN_BADQACC", "a non-finite acceleration: it reset its state"},
      {mjWARN_BADQVEL, "mjWARN_BADQVEL", "a non-finite velocity: it reset its state"},
      {mjWARN_BADQPOS, "mjWARN_BADQPOS", "a non-finite position: it reset its state"},
  };
  for (const auto& k : kinds) {
    if (d->warning[k.index].number > 0) return std::string(k.name) + " (" + k.meaning + ")";
  }
  return "";
}

bool mujoco_buffer_full(const std::string& reason) {
  return reason.find("mjWARN_CONTACTFULL") != std::string::npos ||
         reason.find("mjWARN_CNSTRFULL") != std::string::npos;
}

std::string mujoco_hint(const Scene& scene, const std::string& reason) {
  if (mujoco_buffer_full(reason)) {
    return "the scene has more contacts than the export sizes MuJoCo's buffers for "
           "(reference/mjcf_export.h mjcf_size; MuJoCo 2.2 keeps its constraint rows in dense "
           "arrays, capped to fit its one buffer): compare a scene with fewer bones in contact";
  }
  const double dt = scene.params.dt;
  return "MuJoCo's Euler step is unstable at dt " + message_number(dt) +
         " s on this scene's springs; try a smaller step, e.g. --set dt=" +
         message_number(dt / 10) + " with --steps ten times the scene's (the same duration)";
}

RunSummary run_mujoco(const Scene& scene, ReferenceMode mode, const StepObserver& observer,
                      bool observe_initial) {
  const auto t0 = std::chrono::steady_clock::now();
  MujocoReference ref(scene, mode);
  if (observer && observe_initial) observer(ref.state(), initial_stats(scene, ref.state()));
  // the same rules as run_scene; MuJoCo's bad qacc/qvel/qpos warning counts as non-finite
  RunMonitor monitor(scene, "MuJoCo: ");
  // the violation in MuJoCo's own joints: hinges wherever an axis is locked (exact-constraints
  // mode, and same-forces mode of the joint-space schemes) read as the engine's hinge and
  // universal joints (kRemoved); balls (same-forces mode of the paper's scheme) by the rotation
  // vector. The scene's scheme alone would read a gauss-seidel scene's hinges as balls.
  const LockedAxes joints = joint_model(mode, scene.params) == JointModel::kBallJoints
                                ? LockedAxes::kSprings
                                : LockedAxes::kRemoved;
  std::string warning;  // mujoco_warning, with its step
  for (int k = 0; k < scene.steps; ++k) {
    const StepStats st = ref.step();
    StepObservation obs = observe_step(scene, ref.state(), st);
    if (joints != scene.params.locked_axes())
      obs.limit_violation = max_limit_violation(scene.rig, joints, ref.state().pose);
    obs.engine_non_finite = ref.bad_acceleration();
    const bool stop = monitor.observe(obs);
    if (observer) observer(ref.state(), st);
    warning = mujoco_warning(ref.model(), ref.data());
    if (!warning.empty()) warning += " at step " + std::to_string(ref.state().step);
    if (stop || !warning.empty()) break;
  }
  RunSummary out = monitor.summary();
  if (!warning.empty()) {  // not comparable: said as MuJoCo said it
    out.converged = false;
    out.diverged = true;
    out.divergence_reason = "MuJoCo raised " + warning + ": not comparable";
  }
  monitor.fill_final(scene, ref.state(), out);
  out.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return out;
}

}  // namespace physik
