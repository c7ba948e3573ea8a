// The contacts' data: what a run finds and carries, owned by the state (SimState::contact) and
// passed explicitly, as the Rig and Scene are the model (the contact model: physik/model/
// contact_model.h). The collision world (FCL's objects, collision.h), the contacts the last
// force stage found and the implicit elements it emitted, the self-contacts per bone, the static
// friction's anchors (ground_contacts.h), and the contacts of the last potential query. Nothing in
// the engine builds a collision world of its own: every detection goes through one of these.
//
// Detection (collision.h) lists a state's contacts in one order, which every stage keeps: the
// ground's, bone by bone; the obstacles', obstacle by obstacle; then the bone pairs', (a, b),
// a < b. The ground and obstacle contacts are ground_contacts.h's force, the bone pairs
// self_contacts.h's.
// Units: rig units, N, N/m, N s/m, s.
#pragma once

#include <vector>

#include "physik/engine/collision.h"
#include "physik/model/scene.h"

namespace physik {

// A contact's static friction (ground_contacts.h): its tangential anchor spring's stretch, as the
// last force stage left it. The stretch now is stretch_world + step v_t, v_t the relative
// velocity at point_world now, tangent to normal_world, no longer than limit.
struct FrictionAnchor {
  int bone = -1;  // the contact's bodies and feature (collision.h Contact)
  int other_bone = -1;
  int obstacle = -1;
  int feature = 0;
  Vec3 point_world = Vec3::Zero();    // rig units, the contact point at that force stage
  Vec3 normal_world = Vec3::UnitZ();  // unit, its normal then
  Vec3 stretch_world = Vec3::Zero();  // rig units, the spring's stretch then, tangent to normal
  double step = 0.0;                  // s, the step that force stage was taken over
  double limit = 0.0;                 // rig units, mu F_n / k_t: the stretch at which it slips
};

// A contact as the implicit step sees it (implicit_step.h): a point element on `bone`, and with
// the opposite sign on `other_bone` when it is a bone (-1: the ground or an obstacle).
struct ContactElement {
  int bone = -1;
  int other_bone = -1;
  Vec3 point_world = Vec3::Zero();  // rig units
  Mat3 stiffness = Mat3::Zero();    // N/m, K = -dF/dx of a's point relative to b's, world axes
  Mat3 damping = Mat3::Zero();      // N s/m, D = -dF/dv of the same, world axes
};

struct ContactData {
  CollisionWorld world;                  // FCL's objects, built by prepare
  std::vector<Contact> found;            // the last force stage's contacts, detection order
  std::vector<ContactElement> elements;  // those that push, for the implicit step
  std::vector<int> self_count;           // (nbone) bone-bone contacts per bone, found by the last
                                         //   force stage (self_contacts.h's cap)
  std::vector<FrictionAnchor> anchors;   // the static friction of the last force stage's ground
                                         //   and obstacle contacts that push, detection order
  std::vector<FrictionAnchor> anchors_next;  // the force stage's scratch
  std::vector<Contact> at_frames;  // the contacts of the last potential query (potential.h)
  std::vector<Contact> reached;    // the ground contacts a rejected implicit (sub)step reached
                                   //   (implicit_advance.h), bone-local
};

// Size the data for a scene (room for the contacts, the FCL objects built), so that a run's steps
// allocate nothing for them; nothing for a scene without contacts.
void prepare_contact_data(const Scene& scene, ContactData& data);

// The contacts of a pose for a check before a run (start_contacts.h, bone_overlaps.h, the run
// monitor's start: potential.h initial_potential_energy), in detection order: the one place outside
// a run's state that builds a collision world, once per call. A run's stages detect through their
// state's data instead.
std::vector<Contact> contacts_at_pose(const Scene& scene, const BoneFrames& frames);

// Every contact of the scene's bones at `frames`, into `out` (cleared first), in detection order.
void detect_contacts(const Scene& scene, const BoneFrames& frames, ContactData& data,
                     std::vector<Contact>& out);

// The force stage's detection: the contacts at the state's frames into data.found, the
// self-contacts per bone counted, the implicit elements cleared (the contact forces refill them).
void detect_step_contacts(const Scene& scene, const BoneFrames& frames, ContactData& data);

// The deepest overlap of a set of contacts, in rig units and as a fraction of the radius of the
// thinner capsule of its contact (a bone's own radius is what a penetration is measured against).
struct Penetration {
  int contacts = 0;
  double max_depth = 0.0;           // rig units
  double max_depth_fraction = 0.0;  // 1, of the thinner touching bone's collision radius
};
Penetration penetration(const Scene& scene, const std::vector<Contact>& contacts);
// ... of the contacts at `frames` (detected through `data`)
Penetration penetration(const Scene& scene, const BoneFrames& frames, ContactData& data);

}  // namespace physik
