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

}  // namespace

void apply_gravity(const Scene& scene, SimState& s) {
  const Vec3& g = scene.gravity_world;
  if (g.isZero(0.0)) return;
  for (int i = 0; i < scene.rig.nbone; ++i) s.force_world[i] += scene.rig.bone_mass[i] * g;
}

void apply_contacts(const Scene& scene, SimState& s) {
  s.contact_elements.clear();
  s.contacts.clear();
  if (!scene.collision.any()) return;
  s.collision_world.detect(scene, s.frames, s.contacts);
  const EngineParams& p = scene.params;
  for (Contact& c : s.contacts) {
    const Vec3& n = c.normal_world;
    Vec3 v = point_velocity(s, c.bone, c.point_world);
    if (c.other_bone >= 0) v -= point_velocity(s, c.other_bone, c.point_world);
    const double vn = v.dot(n);
    const double fn = p.contact_k * c.depth - p.contact_damping * vn;
    c.normal_force = std::max(fn, 0.0);
    if (!(fn > 0.0)) continue;  // separating faster than the spring pushes: no force
    const Vec3 vt = v - vn * n;
    const double friction_damping = p.friction * fn / std::max(vt.norm(), p.friction_speed);
    const Vec3 f = fn * n - friction_damping * vt;
    apply_force_at(s, c.bone, f, c.point_world);
    if (c.other_bone >= 0) apply_force_at(s, c.other_bone, -f, c.point_world);
    // the implicit step's element (contacts.h)
    const Mat3 nn = n * n.transpose();
    ContactElement e;
    e.bone = c.bone;
    e.other_bone = c.other_bone;
    e.point_world = c.point_world;
    e.stiffness = p.contact_k * nn;
    e.damping = p.contact_damping * nn + friction_damping * (Mat3::Identity() - nn);
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
