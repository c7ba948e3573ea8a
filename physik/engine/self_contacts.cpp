#include "physik/engine/self_contacts.h"

#include <algorithm>

#include "physik/engine/implicit_elements.h"
#include "physik/engine/newton_euler.h"

namespace physik {

namespace {

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

// the most a self-contact's explicit damper and friction may damp its relative motion over a step
// of h, N s/m: 1 / (h W_c), W_c = n_a w_a(p) + n_b w_b(p) (self_contacts.h)
double self_contact_damping_cap(const Rig& rig, const SimState& s, const Contact& c, double h) {
  const double w =
      s.contact.self_count[c.bone] * compliance_bound(rig, s, c.bone, c.point_world) +
      s.contact.self_count[c.other_bone] * compliance_bound(rig, s, c.other_bone, c.point_world);
  return 1.0 / (h * w);
}

}  // namespace

void apply_self_contacts(const Scene& scene, SimState& s, double h) {
  if (!scene.collision.self_collision) return;
  ContactData& d = s.contact;
  const EngineParams& p = scene.params;
  for (Contact& c : d.found) {
    if (c.other_bone < 0) continue;  // the ground or an obstacle: ground_contacts.h
    const Vec3& n = c.normal_world;
    const Vec3 v =
        point_velocity(s, c.bone, c.point_world) - point_velocity(s, c.other_bone, c.point_world);
    // the damper and friction: explicit, capped for the step (above)
    const double cap = self_contact_damping_cap(scene.rig, s, c, h);
    const double damping = std::min(p.contact_damping, cap);
    const double vn = v.dot(n);
    const double fn = p.contact_k * c.depth - damping * vn;
    c.normal_force = std::max(fn, 0.0);
    if (!(fn > 0.0)) continue;  // separating faster than the spring pushes: no force
    const Vec3 vt = v - vn * n;
    const double friction_damping =
        std::min(p.friction * fn / std::max(vt.norm(), p.friction_speed), cap);
    const Vec3 f = fn * n - friction_damping * vt;
    apply_force_at(s, c.bone, f, c.point_world);
    apply_force_at(s, c.other_bone, -f, c.point_world);
    // the implicit step's element: the spring alone (above)
    ContactElement e;
    e.bone = c.bone;
    e.other_bone = c.other_bone;
    e.point_world = c.point_world;
    const Mat3 nn = n * n.transpose();
    e.stiffness = p.contact_k * nn;
    d.elements.push_back(e);
  }
}

double self_contact_potential(const Scene& scene, const std::vector<Contact>& contacts) {
  double u = 0.0;
  for (const Contact& c : contacts) {
    if (c.other_bone >= 0) u += 0.5 * scene.params.contact_k * c.depth * c.depth;
  }
  return u;
}

double self_contacts_potential(const Scene& scene, const SimState& s) {
  if (!scene.collision.self_collision) return 0.0;
  return self_contact_potential(scene, s.contact.at_frames);
}

void self_contacts_rate(const Scene&, double h, SimState& s) {
  for (const ContactElement& e : s.contact.elements) {
    if (e.other_bone < 0) continue;
    // b moves on at its start-of-step velocity: K times the relative velocity, on a and on b
    const Vec3 v =
        point_velocity(s, e.bone, e.point_world) - point_velocity(s, e.other_bone, e.point_world);
    const Vec3 f = -h * (e.stiffness * v);
    apply_force_at(s, e.bone, f, e.point_world);
    apply_force_at(s, e.other_bone, -f, e.point_world);
  }
}

void self_contacts_augment(const Scene&, double h, SimState& s) {
  ArticulatedBodyData& d = s.joint_space.articulated;
  for (const ContactElement& e : s.contact.elements) {
    if (e.other_bone < 0) continue;
    const Mat3 A = 2.0 * (h * h * e.stiffness + h * e.damping);  // the split spring, twice
    for (const int b : {e.bone, e.other_bone}) {
      add_point_element(A, e.point_world - d.point_world[b], s.implicit.accel_bias[b],
                        d.inertia_art[b], d.bias_force[b]);
    }
  }
}

}  // namespace physik
