// Contact forces, gravity and their potentials (contacts.h).
#include "physik/engine/contacts.h"

#include <algorithm>
#include <tuple>

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

// the order the force stage lists a state's contacts in (collision.h detect): the ground's, the
// obstacles' by obstacle, then the bone pairs'; each by bone, then feature
bool contact_before(const FrictionAnchor& a, const Contact& c) {
  const auto group = [](int other_bone, int obstacle) {
    return other_bone >= 0 ? 2 : (obstacle >= 0 ? 1 : 0);
  };
  return std::make_tuple(group(a.other_bone, a.obstacle), a.obstacle, a.bone, a.other_bone,
                         a.feature) < std::make_tuple(group(c.other_bone, c.obstacle), c.obstacle,
                                                      c.bone, c.other_bone, c.feature);
}

bool same_contact(const FrictionAnchor& a, const Contact& c) {
  return a.bone == c.bone && a.other_bone == c.other_bone && a.obstacle == c.obstacle &&
         a.feature == c.feature;
}

// the anchor of the last force stage's contact that `c` continues, or null (a new contact)
const FrictionAnchor* find_anchor(const std::vector<FrictionAnchor>& anchors, const Contact& c) {
  const auto it = std::lower_bound(anchors.begin(), anchors.end(), c, contact_before);
  return it != anchors.end() && same_contact(*it, c) ? &*it : nullptr;
}

Vec3 clamp_length(const Vec3& x, double limit) {
  const double len = x.norm();
  return len > limit ? Vec3(x * (limit / len)) : x;
}

// the stretch an anchor's spring is carried to now, before its limit: stretch + step v_t, v_t the
// tangential relative velocity at its point now; rig units
Vec3 carried_stretch(const SimState& s, const FrictionAnchor& a) {
  Vec3 v = point_velocity(s, a.bone, a.point_world);
  if (a.other_bone >= 0) v -= point_velocity(s, a.other_bone, a.point_world);
  const Vec3& n = a.normal_world;
  return a.stretch_world + a.step * (v - v.dot(n) * n);
}

// its stretch now: at most its limit (the contact slips there)
Vec3 current_stretch(const SimState& s, const FrictionAnchor& a) {
  return clamp_length(carried_stretch(s, a), a.limit);
}

// a ground or obstacle contact's anchor spring at this force stage: the stretch carried over
// from the contact it continues, turned into this contact's tangent plane and held at `limit`
// (mu F_n / k_t), and whether it slips; the contact's anchor is listed for the next force stage
struct AnchorNow {
  Vec3 stretch = Vec3::Zero();  // rig units
  bool slipping = false;        // it slid over the last step, and slides on
};

AnchorNow anchor_contact(SimState& s, const Contact& c, double limit, double h) {
  AnchorNow out;
  const Vec3& n = c.normal_world;
  if (const FrictionAnchor* a = find_anchor(s.friction_anchors, c)) {
    out.stretch = carried_stretch(s, *a);
    out.stretch -= out.stretch.dot(n) * n;
    out.slipping = out.stretch.norm() >= limit;
    out.stretch = clamp_length(out.stretch, limit);
  }
  FrictionAnchor next;
  next.bone = c.bone;
  next.other_bone = c.other_bone;
  next.obstacle = c.obstacle;
  next.feature = c.feature;
  next.point_world = c.point_world;
  next.normal_world = n;
  next.stretch_world = out.stretch;
  next.step = h;
  next.limit = limit;
  s.friction_anchors_next.push_back(next);
  return out;
}

// the anchor spring's stiffness, N/m: k_t along the tangent plane, but none along the slip of a
// slipping one (it pulls a constant mu F_n there)
Mat3 anchor_stiffness(const AnchorNow& anchor, const Mat3& tangent, double k_t) {
  if (!anchor.slipping) return k_t * tangent;
  const Vec3 slip = anchor.stretch.normalized();
  return k_t * (tangent - slip * slip.transpose());
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
  s.friction_anchors_next.clear();
  if (!scene.collision.any()) {
    s.friction_anchors.clear();
    return;
  }
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
    const double coulomb = p.friction * fn;  // N, the most the friction can pull
    // static friction (a ground or obstacle contact)
    const bool anchored = !self && p.friction_stiffness > 0.0 && coulomb > 0.0;
    const AnchorNow anchor =
        anchored ? anchor_contact(s, c, coulomb / p.friction_stiffness, h) : AnchorNow{};
    const Vec3& stretch = anchor.stretch;
    // the viscous share: what the spring leaves of mu F_n, over max(|v_t|, v_s)
    const double spring_pull = p.friction_stiffness * stretch.norm();
    double friction_damping =
        std::max(coulomb - spring_pull, 0.0) / std::max(vt.norm(), p.friction_speed);
    if (self) friction_damping = std::min(friction_damping, cap);
    const Vec3 f = fn * n - p.friction_stiffness * stretch - friction_damping * vt;
    apply_force_at(s, c.bone, f, c.point_world);
    if (self) apply_force_at(s, c.other_bone, -f, c.point_world);
    // the implicit step's element (contacts.h): a self-contact's spring alone
    const Mat3 nn = n * n.transpose();
    const Mat3 tangent = Mat3::Identity() - nn;
    ContactElement e;
    e.bone = c.bone;
    e.other_bone = c.other_bone;
    e.point_world = c.point_world;
    e.stiffness = p.contact_k * nn;
    if (anchored) e.stiffness += anchor_stiffness(anchor, tangent, p.friction_stiffness);
    if (!self) e.damping = damping * nn + friction_damping * tangent;
    s.contact_elements.push_back(e);
  }
  // the anchors, in the contacts' order (collision.h detect), for the next force stage
  std::swap(s.friction_anchors, s.friction_anchors_next);
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

double friction_potential(const Scene& scene, const SimState& s) {
  double u = 0.0;
  for (const FrictionAnchor& a : s.friction_anchors) {
    u += 0.5 * scene.params.friction_stiffness * current_stretch(s, a).squaredNorm();
  }
  return u;
}

double contact_potential(const Scene& scene, const SimState& s) {
  if (!scene.collision.any()) return 0.0;
  s.collision_world.detect(scene, s.frames, s.contact_scratch);
  return contact_potential(scene, s.contact_scratch) + friction_potential(scene, s);
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
