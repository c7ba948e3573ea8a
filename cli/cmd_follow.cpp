// physik follow CLIP --rig RIG: the PhysIK engine follows a BVH clip of the rig's source skeleton
// with control points on chosen bones (physik/io/clip_follow.h), into a run folder as `simulate`
// writes it (`physik view <out>` plays it). Exit 3 if the run diverges.
#include <algorithm>
#include <iostream>
#include <memory>

#include "cli/commands.h"
#include "physik/engine/run_monitor.h"
#include "physik/io/bvh.h"
#include "physik/io/clip_follow.h"
#include "physik/io/output_files.h"
#include "physik/io/rig_io.h"
#include "physik/io/run_folder.h"
#include "physik/io/scene_io.h"
#include "physik/model/errors.h"

namespace physik::cli {

namespace {

struct FollowCliOptions {
  std::string clip, rig, out = "out", frames, bvh;
  std::vector<std::string> points, set;
  double ground = 0.0;
  bool no_ground = false, gravity = false, quiet = false, own_skeleton = false;
  int every = 1;
};

// BONE, BONE:head or BONE:tail (the last colon splits, so a bone name may hold colons)
FollowPoint parse_point(const std::string& text) {
  const std::size_t colon = text.rfind(':');
  if (colon != std::string::npos) {
    const std::string at = text.substr(colon + 1);
    if (at == "head" || at == "tail") return {text.substr(0, colon), at == "head" ? 0.0 : 1.0};
  }
  return {text, 1.0};
}

// A:B (clip frames from 0, inclusive), A: or :B
void parse_frames(const std::string& text, FollowOptions& o) {
  if (text.empty()) return;
  const std::size_t colon = text.find(':');
  auto number = [&](const std::string& t, int fallback) {
    if (t.empty()) return fallback;
    std::size_t used = 0;
    int v = 0;
    try {
      v = std::stoi(t, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != t.size() || v < 0) {
      throw_input_error("--frames", "", "",
                        "expected FIRST:LAST, frame numbers from 0, got '" + text + "'");
    }
    return v;
  };
  if (colon == std::string::npos) {
    throw_input_error("--frames", "", "", "expected FIRST:LAST (e.g. 0:120), got '" + text + "'");
  }
  o.first = number(text.substr(0, colon), 0);
  o.last = number(text.substr(colon + 1), -1);
}

// a --set dt that does not divide the clip's frame time plays the clip at another speed: say so
void warn_clip_speed(const BvhFile& clip, const Scene& scene) {
  const double t = follow_frame_time(scene);
  if (std::abs(t - clip.frame_time) <= 1e-6 * clip.frame_time) return;
  const int n = follow_steps_per_frame(scene);
  std::cerr << "physik: warning: follow: a clip frame takes " << t << " s (" << n
            << (n == 1 ? " step" : " steps") << " of dt " << scene.params.dt
            << " s) against the clip's " << clip.frame_time
            << " s: the run (and --bvh) plays the clip at " << clip.frame_time / t
            << " times its speed\n";
}

void run_follow(const FollowCliOptions& c) {
  if (c.every < 1) throw_input_error("--every", "", "", "must be at least 1");
  FollowOptions fo;
  fo.source = c.clip;
  parse_frames(c.frames, fo);
  for (const std::string& p : c.points) fo.points.push_back(parse_point(p));
  if (!c.no_ground) fo.ground = c.ground;
  fo.gravity = c.gravity;
  const ParamOverrides overrides = parse_param_overrides(c.set, "--set");
  if (!c.bvh.empty()) check_output_file(c.bvh, "--bvh");
  const Rig rig = load_rig(c.rig);
  const BvhFile clip = read_bvh_file(c.clip);
  Scene scene = follow_scene(rig, clip, follow_params(rig, clip, fo, overrides), fo);
  scene.rig_file = c.rig;
  warn_start_contacts(scene);
  if (!c.quiet) {
    std::cerr << "follow: " << scene.control_points.size() << " points over "
              << scene.schedule.size() / std::max<std::size_t>(1, scene.control_points.size()) + 1
              << " clip frames, " << scene.steps << " steps of " << scene.params.dt
              << " s, control_k " << scene.params.control_k << " N/m\n";
  }
  warn_clip_speed(clip, scene);
  // one BVH frame per clip frame (followed_frame), at the engine's time per clip frame
  std::unique_ptr<BvhRecorder> bvh;
  if (!c.bvh.empty()) {
    BvhExportOptions bo;
    bo.source_skeleton = !c.own_skeleton;
    bvh = std::make_unique<BvhRecorder>(scene.rig, follow_frame_time(scene), 1, bo);
    bvh->record(scene.initial_pose);
  }
  clear_run_folder(c.out, "--out");
  const int report_every = std::max(1, scene.steps / 10);
  const RunSummary sum =
      simulate_into_folder(scene, c.out, c.every, [&](const SimState& s, const StepStats& st) {
        if (bvh && followed_frame(scene, s.step) > 0 && std::isfinite(st.kinetic_energy)) {
          bvh->record(s.frames);
        }
        if (!c.quiet && s.step % report_every == 0) {
          std::cerr << "  step " << s.step << "/" << scene.steps << "  KE " << st.kinetic_energy
                    << " J  max residual " << st.max_residual << "\n";
        }
      });
  if (bvh) print_bvh_report(c.bvh, bvh->save(c.bvh));
  if (!c.quiet) std::cerr << "follow: " << sum.steps_run << " steps -> " << c.out << "\n";
  if (sum.diverged) {
    std::cerr << "physik: diverged: " << sum.divergence_reason << "; " << divergence_hint(scene)
              << "\n";
    throw DivergedRun(sum.divergence_reason);
  }
}

}  // namespace

void add_follow_commands(CLI::App& app) {
  auto c = std::make_shared<FollowCliOptions>();
  auto* cmd = app.add_subcommand(
      "follow",
      "Follow a BVH clip with the PhysIK engine: control points on chosen bones track the "
      "clip's joints frame by frame (at the clip's speed), on a floor, into a run folder as "
      "`simulate` writes it (`physik view <out>` plays it). The rig must be made from the clip's "
      "skeleton (`physik rig from-bvh`). Exit 3 if the run diverges.");
  cmd->add_option("CLIP", c->clip, "BVH or qBVH clip of the rig's source skeleton")->required();
  cmd->add_option("--rig", c->rig, "Rig file made from the clip's skeleton (JSON)")->required();
  cmd->add_option("--out", c->out, "Output folder")->capture_default_str();
  cmd->add_option("--point", c->points,
                  "A followed point: BONE (its tail), BONE:tail or BONE:head; repeat for more "
                  "(default: the root bone's tail and every leaf bone's tail)");
  cmd->add_option("--frames", c->frames, "FIRST:LAST clip frames, from 0 (default: all)");
  cmd->add_option("--ground", c->ground, "The floor's height (rig units, rig Z up)")
      ->capture_default_str();
  cmd->add_flag("--no-ground", c->no_ground, "No floor");
  cmd->add_flag("--gravity", c->gravity, "Gravity, -9.81 rig units/s^2 along Z");
  cmd->add_option("--set", c->set,
                  "Override an engine parameter, as simulate's --set (defaults: dt the clip's "
                  "frame time, split into steps of at most 1/120 s; control_k = M g / (n x 0.01): "
                  "the n followed points holding the rig's weight would sag 0.01 rig units)");
  cmd->add_option("--every", c->every, "Write a CSV row every N steps")->capture_default_str();
  cmd->add_option("--bvh", c->bvh,
                  "Also record the run as a BVH animation (on the rig's source skeleton): one "
                  "frame per clip frame, at the clip's frame time");
  cmd->add_flag("--own-skeleton", c->own_skeleton, kOwnSkeletonHelp);
  cmd->add_flag("--quiet", c->quiet, "No progress output");
  cmd->callback([c] { run_follow(*c); });
}

}  // namespace physik::cli
