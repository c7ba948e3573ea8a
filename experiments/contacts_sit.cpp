// The contacts experiment's sit study (experiments/contacts.cpp):
//   sit   Fig 11's sitting pose (the paper's scene run as shipped, no gravity) with a seat (a box
//         whose top is at the bottom of the thighs' capsules there, from behind the pelvis to
//         short of the knees) and a floor (at the feet's lowest point), gravity switched on, the
//         targets at their last values: do the pelvis, hips or thighs rest on the seat and the
//         feet on the floor, the deepest penetration at rest (the target: 5% of the radius),
//         and the gap to MuJoCo's resting pose over the rig's height. The implicit scheme at dt
//         0.01 (MuJoCo's Euler needs dt well under its solref of 0.02 s), run 30 s as the
//         drops (at 10 s the arms were still moving onto the floor). Starting from the
//         standing pose instead, the pelvis spring (k = 30) could not hold the rig's weight on
//         the way down: this asks only whether the rig stays seated.
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "experiments/common.h"
#include "experiments/contacts.h"
#include "experiments/contacts_scenes.h"
#include "experiments/report.h"
#include "physik/engine/contact_data.h"
#include "physik/engine/engine.h"
#include "physik/io/scene_io.h"
#include "reference/compare.h"

namespace physik::experiments::contacts_study {

namespace {

// --- sit: Fig 11 with a seat and a floor ----------------------------------------------------

// the paper's Fig 11 run as shipped (no gravity, no contacts): its last pose, local rotations
Pose paper_sitting_pose(const Scene& paper) {
  SimState st;
  init_state(paper, st);
  for (int k = 0; k < paper.steps; ++k) step(paper, st);
  return st.pose;
}

// the seat under the sitting pose: its top at the lowest point of the thighs' capsules, from
// 0.5 behind the pelvis (+y is behind: the paper's pelvis moves to +y) to a thigh radius short
// of the knees (so the shins hang in front of it), 0.3 wider than the hips on each side, 0.4
// thick; the floor at the lowest point of the feet's capsules
void add_seat_and_floor(Scene& s, const BoneFrames& f) {
  const Rig& rig = s.rig;
  const int pelvis = rig.find_bone("torso"), thigh_l = rig.find_bone("thigh.L"),
            thigh_r = rig.find_bone("thigh.R");
  const double top = std::min(capsule_bottom(s.rig, f, thigh_l), capsule_bottom(s.rig, f, thigh_r));
  const double back = f.tail_world[pelvis].y() + 0.5;
  const double front = std::max(f.tail_world[thigh_l].y(), f.tail_world[thigh_r].y()) +
                       2.0 * rig.bone_collision_radius[thigh_l];
  const double half_x =
      std::max(std::abs(f.head_world[thigh_l].x()), std::abs(f.head_world[thigh_r].x())) + 0.3;
  BoxObstacle seat;
  seat.name = "seat";
  seat.half_extents = Vec3(half_x, 0.5 * (back - front), 0.2);
  seat.center_world = Vec3(0.0, 0.5 * (back + front), top - 0.2);
  s.collision.obstacles = {seat};
  const double floor = std::min(capsule_bottom(s.rig, f, rig.find_bone("foot.L")),
                                capsule_bottom(s.rig, f, rig.find_bone("foot.R")));
  s.collision.ground = GroundPlane{Vec3::UnitZ(), floor};
}

// Fig 11's scene from its sitting pose, targets at their last values, gravity on, with a seat
// and a floor; the implicit scheme at dt 0.01 with the original's damping (3 N s/m)
Scene sit_scene(const Context& ctx) {
  Scene s = scene_named(ctx, "fig11_sit");
  s.initial_pose = paper_sitting_pose(s);
  for (const TargetChange& t : s.schedule)
    s.control_points[t.control_point].target_world = t.target_world;
  s.schedule.clear();
  s.params.scheme = Scheme::kImplicit;
  s.params.dt = 0.01;
  s.params.damping_auto = false;
  s.params.damping = 3.0;
  s.params.interpolation = Interpolation::kNone;
  s.steps = ctx.quick ? 100 : 3000;  // 30 s, as the drops: at 10 s the arms still moved
  s.gravity_world = Vec3(0, 0, -9.81);
  add_seat_and_floor(s, forward_kinematics(s.rig, s.initial_pose));
  s.file = "contacts_sit";
  return s;
}

struct Seated {
  std::vector<std::string> on_seat, on_floor;  // the bones touching the seat, the floor
  bool feet_on_floor = false;                  // both feet's bones touch the floor
  bool hips_on_seat = false;                   // the pelvis, a hip or a thigh on the seat
  double penetration = 0.0;                    // 1, of the radius, the deepest contact
};

// which bones touch what at a pose (PhysIK's detection), and how deep
Seated seated(const Scene& s, const BoneFrames& f) {
  const std::vector<Contact> contacts = contacts_at_pose(s, f);
  Seated out;
  for (const Contact& c : contacts) {
    auto& list = c.obstacle >= 0 ? out.on_seat : out.on_floor;
    const std::string& name = s.rig.bone_name[c.bone];
    if (std::find(list.begin(), list.end(), name) == list.end()) list.push_back(name);
  }
  const auto has = [](const std::vector<std::string>& l, const char* n) {
    return std::find(l.begin(), l.end(), n) != l.end();
  };
  out.feet_on_floor = has(out.on_floor, "foot.L") && has(out.on_floor, "foot.R");
  for (const char* b : {"torso", "hip.L", "hip.R", "thigh.L", "thigh.R"}) {
    out.hips_on_seat = out.hips_on_seat || has(out.on_seat, b);
  }
  out.penetration = penetration(s, contacts).max_depth_fraction;
  return out;
}

nlohmann::json to_json(const Seated& m) {
  return {{"bones_on_seat", m.on_seat},
          {"bones_on_floor", m.on_floor},
          {"feet_on_floor", m.feet_on_floor},
          {"pelvis_or_thighs_on_seat", m.hips_on_seat},
          {"penetration_over_radius", m.penetration}};
}

std::string joined(const std::vector<std::string>& names) {
  std::string out;
  for (const std::string& n : names) out += (out.empty() ? "" : ", ") + n;
  return out.empty() ? "none" : out;
}

// the feet that do not touch the floor, named: "foot.L", "foot.L and foot.R" (or "none")
std::string feet_off_floor(const Seated& m) {
  std::vector<std::string> off;
  for (const char* foot : {"foot.L", "foot.R"}) {
    if (std::find(m.on_floor.begin(), m.on_floor.end(), foot) == m.on_floor.end()) {
      off.emplace_back(foot);
    }
  }
  return off.size() == 2 ? off[0] + " and " + off[1] : joined(off);
}

// the largest endpoint distance between two poses (reference/compare.h pose_gap) over the bones
// that are not an arm's (collar, upper_arm, forearm, hand), rig units
double gap_without_arms(const Rig& rig, const BoneFrames& a, const BoneFrames& b) {
  double g = 0.0;
  for (int i = 0; i < rig.nbone; ++i) {
    const std::string& name = rig.bone_name[i];
    bool arm = false;
    for (const char* prefix : {"collar", "upper_arm", "forearm", "hand"}) {
      arm = arm || name.rfind(prefix, 0) == 0;
    }
    if (arm) continue;
    g = std::max({g, (a.head_world[i] - b.head_world[i]).norm(),
                  (a.tail_world[i] - b.tail_world[i]).norm()});
  }
  return g;
}

// the report's note on the sit's floor: at the lower foot, the other foot above it
void sit_foot_note(const Scene& scene, Report& report) {
  const BoneFrames f0 = forward_kinematics(scene.rig, scene.initial_pose);
  const double foot_gap = std::abs(capsule_bottom(scene.rig, f0, scene.rig.find_bone("foot.L")) -
                                   capsule_bottom(scene.rig, f0, scene.rig.find_bone("foot.R")));
  report.note(
      "Sit: the floor is at the lower foot's lowest point in the paper's sitting pose; the "
      "other foot stands " +
      num(foot_gap) +
      " rig units higher there (the paper's heel and toe targets of the two feet differ), "
      "held by its springs.");
}

}  // namespace

nlohmann::json sit_section(const Context& ctx, Report& report) {
  const Scene scene = checked_start(sit_scene(ctx));
  const Comparison c = compare_with_mujoco(scene, ReferenceMode::kSameForces);
  write_run_folder(ctx, "sit", scene);
  const bool physik_diverged = c.physik.summary.diverged, mujoco_ran = !c.mujoco.summary.diverged;
  const Seated p = seated(scene, c.physik.summary.final_frames);
  const Seated m = seated(scene, c.mujoco.summary.final_frames);
  const double ke = c.physik.summary.final_kinetic_energy;
  const double gap = c.gap.final_pose_gap / scene.rig.height();
  report.claim(
      "Fig 11 with a seat and a floor: the rig sits on the seat, with its feet on the floor",
      "after " + num(scene.steps * scene.params.dt) + " s under gravity: on the seat " +
          joined(p.on_seat) + "; on the floor " + joined(p.on_floor) + "; KE " + num(ke) +
          " J (MuJoCo: seat " + joined(m.on_seat) + "; floor " + joined(m.on_floor) + ")",
      physik_diverged                     ? "no (the run diverged)"
      : p.hips_on_seat && p.feet_on_floor ? "yes"
      : p.hips_on_seat ? "partly (on the seat; " + feet_off_floor(p) + " off the floor)"
                       : "no");
  report.named("sit-on-seat");
  report.claim("Seated, no penetration deeper than 5% of a bone's radius",
               "deepest at the end: " + num(p.penetration) +
                   " of the radius (MuJoCo's pose: " + num(m.penetration) + ")",
               p.penetration <= 0.05 ? "yes" : "no");
  const double body_gap =
      gap_without_arms(scene.rig, c.physik.summary.final_frames, c.mujoco.summary.final_frames) /
      scene.rig.height();
  report.claim("The seated pose is MuJoCo's within 2% of the rig height",
               "final pose gap over the rig's height: " + num(gap) +
                   "; without the arms (collars to hands: no control point holds them, and gravity "
                   "lays them on the floor or the seat): " +
                   num(body_gap),
               !mujoco_ran || physik_diverged ? "n/a (a run diverged)"
               : gap <= 0.02                  ? "yes"
                                              : "no");
  sit_foot_note(scene, report);
  const BoxObstacle& seat = scene.collision.obstacles[0];
  nlohmann::json out = {
      {"physik", to_json(p)},
      {"mujoco", to_json(m)},
      {"physik_kinetic_energy", ke},
      {"final_pose_gap_over_height", gap},
      {"final_pose_gap_without_arms_over_height", body_gap},
      {"diverged", physik_diverged},
      {"seat_center", {seat.center_world.x(), seat.center_world.y(), seat.center_world.z()}},
      {"seat_half_extents", {seat.half_extents.x(), seat.half_extents.y(), seat.half_extents.z()}},
      {"floor_height", scene.collision.ground->height}};
  if (ctx.log)
    *ctx.log << "  sit: seat " << joined(p.on_seat) << ", floor " << joined(p.on_floor) << ", gap "
             << num(gap) << "\n";
  return out;
}

}  // namespace physik::experiments::contacts_study
