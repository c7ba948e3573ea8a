// Contact forces, gravity and their potentials (contacts.h).
#include "physik/engine/contacts.h"

#include <algorithm>

#include "physik/engine/measures.h"
#include "physik/engine/newton_euler.h"

namespace physik {

namespace {

// the velocity of the material point of bone b at p, rig units/s
Vec3 point_velocity(const SimState& s, int b, const Vec3& p) {
  return s.vel_world[b] + s.omega_world[b].cross(p - s.com_world[b]);
}

// an upper bound on bone b's compliance at p, 1/kg (the speed a unit impulse at p gives the free
// bone's point there, along any direction; the joints only lower it): with r = p - c_b split
// along the bone (r_axial) and across it (r_perp), |r x f|^2 / I over the principal moments is at
// most (r_perp^2 / I_axial + |r|^2 / I_perp) |f|^2 (only r_perp turns the bone about its axis)
double compliance_bound(const Rig& rig, const SimState& s, int b, const Vec3& p) {
  const Vec3 r = p - s.com_world[b];
  const Vec3 axis = s.frames.tail_world[b] - s.frames.head_world[b];
  const double length2 = axis.squaredNorm();
  const double along = length2 > 0.0 ? r.dot(axis) : 0.0;
  const double r_perp2 =
      std::max(r.squaredNorm() - (length2 > 0.0 ? along * along / length2 : 0.0), 0.0);
  const Vec3& inertia = rig.bone_inertia_local[b];  // local y along the bone
  return 1.0 / rig.bone_mass[b] + r_perp2 / inertia.y() +
         r.squaredNorm() / std::min(inertia.x(), inertia.z());
}

void count_self_contacts(const Rig& rig, SimState& s) {
  // init_state sizes it; a state built otherwise gets it here, once
  if (s.self_contact_count.size() != static_cast<std::size_t>(rig.nbone)) {
    s.self_contact_count.assign(rig.nbone, 0);
  }
  std::fill(s.self_contact_count.begin(), s.self_contact_count.end(), 0);
  for (const Contact& c : s.contacts) {
    if (c.other_bone < 0) continue;
    ++s.self_contact_count[c.bone];
    ++s.self_contact_count[c.other_bone];
  }
}

// the most a self-contact's explicit damper and friction may damp its relative motion over a step
// of h, N s/m: 1 / (h W_c), W_c = n_a w_a(p) + n_b w_b(p) (contacts.h)
double self_contact_damping_cap(const Rig& rig, const SimState& s, const Contact& c, double h) {
  const double w =
      s.self_contact_count[c.bone] * compliance_bound(rig, s, c.bone, c.point_world) +
      s.self_contact_count[c.other_bone] * compliance_bound(rig, s, c.other_bone, c.point_world);
  return 1.0 / (h * w);
}

}  // namespace

void apply_gravity(const Scene& scene, SimState& s) {
  const Vec3& g = scene.gravity_world;
  if (g.isZero(0.0)) return;
  for (int i = 0; i < scene.rig.nbone; ++i) s.force_world[i] += scene.rig.bone_mass[i] * g;
}

void apply_contacts(const Scene& scene, SimState& s, double h) {
  s.contact_elements.clear();
  s.contacts.clear();
  if (!scene.collision.any()) return;
  s.collision_world.detect(scene, s.frames, s.contacts);
  if (scene.collision.self_collision) count_self_contacts(scene.rig, s);
  const EngineParams& p = scene.params;
  for (Contact& c : s.contacts) {
    const bool self = c.other_bone >= 0;
    const Vec3& n = c.normal_world;
    Vec3 v = point_velocity(s, c.bone, c.point_world);
    if (self) v -= point_velocity(s, c.other_bone, c.point_world);
    // a self-contact's damper and friction: explicit, capped for the step (contacts.h)
    const double cap = self ? self_contact_damping_cap(scene.rig, s, c, h) : 0.0;
    const double damping = self ? std::min(p.contact_damping, cap) : p.contact_damping;
    const double vn = v.dot(n);
    const double fn = p.contact_k * c.depth - damping * vn;
    c.normal_force = std::max(fn, 0.0);
    if (!(fn > 0.0)) continue;  // separating faster than the spring pushes: no force
    const Vec3 vt = v - vn * n;
    double friction_damping = p.friction * fn / std::max(vt.norm(), p.friction_speed);
    if (self) friction_damping = std::min(friction_damping, cap);
    const Vec3 f = fn * n - friction_damping * vt;
    apply_force_at(s, c.bone, f, c.point_world);
    if (self) apply_force_at(s, c.other_bone, -f, c.point_world);
    // the implicit step's element (contacts.h): a self-contact's spring alone
    const Mat3 nn = n * n.transpose();
    ContactElement e;
    e.bone = c.bone;
    e.other_bone = c.other_bone;
    e.point_world = c.point_world;
    e.stiffness = p.contact_k * nn;
    if (!self) e.damping = damping * nn + friction_damping * (Mat3::Identity() - nn);
    s.contact_elements.push_back(e);
  }
}

Vec3 gravity_reference(const Scene& scene) {
  if (scene.collision.ground) {
    return scene.collision.ground->height * scene.collision.ground->normal_world;
  }
  return scene.initial_pose.root_head_world;
}

double gravity_potential(const Scene& scene, const BoneFrames& f) {
  const Vec3& g = scene.gravity_world;
  if (g.isZero(0.0)) return 0.0;
  const Vec3 x0 = gravity_reference(scene);
  double u = 0.0;
  for (int i = 0; i < scene.rig.nbone; ++i) {
    u -= scene.rig.bone_mass[i] * g.dot(bone_centre_world(f, i) - x0);
  }
  return u;
}

double contact_potential(const Scene& scene, const std::vector<Contact>& contacts) {
  double u = 0.0;
  for (const Contact& c : contacts) u += 0.5 * scene.params.contact_k * c.depth * c.depth;
  return u;
}

double contact_potential(const Scene& scene, const SimState& s) {
  if (!scene.collision.any()) return 0.0;
  s.collision_world.detect(scene, s.frames, s.contact_scratch);
  return contact_potential(scene, s.contact_scratch);
}

Penetration penetration(const Scene& scene, const std::vector<Contact>& contacts) {
  Penetration out;
  const std::vector<double>& r = scene.rig.bone_collision_radius;
  for (const Contact& c : contacts) {
    ++out.contacts;
    const double radius = c.other_bone >= 0 ? std::min(r[c.bone], r[c.other_bone]) : r[c.bone];
    out.max_depth = std::max(out.max_depth, c.depth);
    out.max_depth_fraction = std::max(out.max_depth_fraction, c.depth / radius);
  }
  return out;
}

Penetration penetration(const Scene& scene, const BoneFrames& frames) {
  CollisionWorld world;
  std::vector<Contact> contacts;
  world.detect(scene, frames, contacts);
  return penetration(scene, contacts);
}

}  // namespace physik
