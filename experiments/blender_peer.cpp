#include "experiments/blender_peer.h"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <thread>
#include <vector>

#include "experiments/common.h"
#include "physik/io/json_fields.h"
#include "physik/io/scene_io.h"
#include "physik/model/errors.h"

extern char** environ;  // POSIX: the environment Blender inherits

namespace physik::experiments {

namespace {

namespace fs = std::filesystem;

bool executable(const std::string& path) {
  std::error_code ec;
  return fs::is_regular_file(path, ec) && ::access(path.c_str(), X_OK) == 0;
}

// `name` itself when it holds a slash, else the first executable `name` on PATH; "" if none.
std::string on_path(const std::string& name) {
  if (name.find('/') != std::string::npos) return executable(name) ? name : "";
  const char* path = std::getenv("PATH");
  std::stringstream dirs(path ? path : "");
  std::string dir;
  while (std::getline(dirs, dir, ':')) {
    const std::string candidate = (dir.empty() ? std::string(".") : dir) + "/" + name;
    if (executable(candidate)) return candidate;
  }
  return "";
}

struct ProcessResult {
  std::string spawn_error;  // the process did not start
  bool timed_out = false;   // killed after the timeout
  int exit_code = -1;       // when it exited
  int signal = 0;           // when a signal ended it
  double seconds = 0.0;
};

// argv[0] is run (no shell) with stdin from /dev/null and stdout + stderr into log_path;
// SIGKILL after timeout_seconds.
ProcessResult run_process(const std::vector<std::string>& argv, const std::string& log_path,
                          double timeout_seconds) {
  ProcessResult r;
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&actions, 1, log_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC,
                                   0644);
  posix_spawn_file_actions_adddup2(&actions, 1, 2);
  std::vector<char*> args;
  for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  const auto t0 = std::chrono::steady_clock::now();
  const auto elapsed = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  };
  pid_t pid = 0;
  const int err = posix_spawn(&pid, args[0], &actions, nullptr, args.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (err != 0) {
    r.spawn_error = std::strerror(err);
    return r;
  }
  int status = 0;
  for (;;) {
    const pid_t done = ::waitpid(pid, &status, WNOHANG);
    if (done == pid) break;
    if (done < 0 && errno != EINTR) {
      r.spawn_error = std::string("waitpid: ") + std::strerror(errno);
      return r;
    }
    if (elapsed() > timeout_seconds) {
      ::kill(pid, SIGKILL);
      while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
      }
      r.timed_out = true;
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  r.seconds = elapsed();
  if (!r.timed_out && WIFEXITED(status)) r.exit_code = WEXITSTATUS(status);
  if (!r.timed_out && WIFSIGNALED(status)) r.signal = WTERMSIG(status);
  return r;
}

// The last line of the log that says something ("Blender quit" says nothing), for a failure's
// one-line reason.
std::string last_log_line(const std::string& log_path) {
  std::ifstream in(log_path);
  std::string line, last;
  while (std::getline(in, line)) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (!line.empty() && line != "Blender quit") last = line;
  }
  return last;
}

// Fields of one CSV line (RFC 4180 quotes, as physik/io/pose_io.h writes them).
std::vector<std::string> csv_fields(const std::string& line) {
  std::vector<std::string> out(1);
  bool quoted = false;
  for (size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quoted) {
      if (c == '"' && i + 1 < line.size() && line[i + 1] == '"') {
        out.back() += '"';
        ++i;
      } else if (c == '"') {
        quoted = false;
      } else {
        out.back() += c;
      }
    } else if (c == '"') {
      quoted = true;
    } else if (c == ',') {
      out.emplace_back();
    } else {
      out.back() += c;
    }
  }
  return out;
}

// The heads and tails of a bones table (pose_io.h) for every bone of the rig.
BoneFrames read_bones(const Rig& rig, const std::string& path) {
  std::ifstream in(path);
  if (!in) throw_input_error(path, "", "", "cannot read file");
  std::string line;
  std::getline(in, line);
  if (!line.empty() && line.back() == '\r') line.pop_back();
  if (line != "bone,parent,head_x,head_y,head_z,tail_x,tail_y,tail_z") {
    throw_input_error(path, "header", "", "not a bones table: '" + line + "'");
  }
  BoneFrames f;
  f.resize(rig.nbone);
  std::vector<int> seen(rig.nbone, 0);
  for (int row = 2; std::getline(in, line); ++row) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty()) continue;
    const std::vector<std::string> v = csv_fields(line);
    const std::string where = "row " + std::to_string(row);
    if (v.size() != 8)
      throw_input_error(path, where, "", "expected 8 fields, got " + std::to_string(v.size()));
    const int b = rig.find_bone(v[0]);
    if (b < 0) throw_input_error(path, where, "bone", "unknown bone '" + v[0] + "'");
    ++seen[b];
    double x[6];
    for (int k = 0; k < 6; ++k) {
      try {
        size_t used = 0;
        x[k] = std::stod(v[2 + k], &used);
        if (used != v[2 + k].size()) throw std::invalid_argument("trailing text");
      } catch (const std::exception&) {
        throw_input_error(path, where, "", "not a number: '" + v[2 + k] + "'");
      }
    }
    f.head_world[b] = Vec3(x[0], x[1], x[2]);
    f.tail_world[b] = Vec3(x[3], x[4], x[5]);
  }
  for (int b = 0; b < rig.nbone; ++b) {
    if (seen[b] != 1) {
      throw_input_error(path, "bone '" + rig.bone_name[b] + "'", "",
                        seen[b] ? "listed more than once" : "missing");
    }
  }
  return f;
}

// The pose file ({"initial_pose": ...}, the scene format) read by the scene loader itself: the
// scene with that initial pose, so every check and message is the scene file's.
Pose read_pose(const Scene& scene, const std::string& path) {
  const nlohmann::json p = read_json_file(path);
  if (!p.is_object() || !p.contains("initial_pose")) {
    throw_input_error(path, "", "initial_pose", "missing");
  }
  nlohmann::json doc = scene_to_json(scene);
  doc["initial_pose"] = p["initial_pose"];
  return scene_from_json(doc, path, fs::path(path).parent_path().string()).initial_pose;
}

}  // namespace

BlenderLocation find_blender() {
  if (const char* env = std::getenv("PHYSIK_BLENDER")) {
    const std::string v = env;
    if (v.empty() || v == "none" || v == "off" || v == "0") {
      return {"", "PHYSIK_BLENDER='" + v + "' turns the Blender peer off"};
    }
    const std::string p = on_path(v);
    if (p.empty()) return {"", "PHYSIK_BLENDER='" + v + "' is not an executable file"};
    return {p, ""};
  }
  const std::string p = on_path("blender");
  if (p.empty()) {
    return {"",
            "Blender not found (no `blender` on PATH, PHYSIK_BLENDER unset; Debian: "
            "apt-get install blender)"};
  }
  return {p, ""};
}

namespace {

// Reads what Blender wrote for a finished run and checks its pose file against its bones: `run`
// becomes "ok", or keeps "failed" with the reason.
void check_itasc_outputs(const Scene& scene, const std::string& csv, const std::string& report,
                         const std::string& pose, ItascRun& run) {
  try {
    run.report = read_json_file(report);
    run.pose = read_pose(scene, pose);
    run.frames = forward_kinematics(scene.rig, run.pose);
    const BoneFrames blender = read_bones(scene.rig, csv);
    for (int b = 0; b < scene.rig.nbone; ++b) {
      run.fk_gap = std::max({run.fk_gap, (run.frames.head_world[b] - blender.head_world[b]).norm(),
                             (run.frames.tail_world[b] - blender.tail_world[b]).norm()});
    }
    if (run.fk_gap > kItascFkGapFraction * scene.rig.height()) {
      run.reason = "iTaSC's pose file and its bones disagree by " + num(run.fk_gap) +
                   " rig units (allowed " + num(kItascFkGapFraction * scene.rig.height()) + ")";
    } else {
      run.status = "ok";
    }
  } catch (const std::exception& e) {
    run.reason = std::string("reading Blender's output: ") + e.what();
  }
}

}  // namespace

ItascRun run_itasc(const Scene& scene, const std::string& script, const std::string& out_dir,
                   double timeout_seconds) {
  ItascRun run;
  const BlenderLocation where = find_blender();
  if (where.path.empty()) {
    run.reason = where.why_not;
    return run;
  }
  run.blender = where.path;
  if (!fs::is_regular_file(script)) {
    run.reason = "the iTaSC script is missing: " + script;
    return run;
  }
  run.status = "failed";
  if (scene.file.empty() || !fs::is_regular_file(scene.file)) {
    run.reason = "the scene has no file for Blender to read ('" + scene.file + "')";
    return run;
  }
  const std::string csv = out_dir + "/itasc_final.csv", report = out_dir + "/itasc_report.json",
                    pose = out_dir + "/itasc_pose.json", log = out_dir + "/itasc_log.txt";
  std::error_code ec;
  for (const std::string& f : {csv, report, pose}) fs::remove(f, ec);
  const ProcessResult p = run_process(
      {run.blender, "-b", "--factory-startup", "--python-exit-code", "1", "--python", script, "--",
       "--scene", scene.file, "--out", csv, "--report", report, "--pose", pose},
      log, timeout_seconds);
  run.seconds = p.seconds;
  const std::string tail = last_log_line(log);
  if (!p.spawn_error.empty()) {
    run.reason = "cannot run " + run.blender + ": " + p.spawn_error;
  } else if (p.timed_out) {
    run.reason =
        "Blender did not finish within " + num(timeout_seconds) + " s and was stopped; see " + log;
  } else if (p.signal != 0) {
    run.reason = "Blender was ended by signal " + std::to_string(p.signal) + "; see " + log;
  } else if (p.exit_code != 0) {
    run.reason = "Blender exited " + std::to_string(p.exit_code) + " (" +
                 (tail.empty() ? std::string("no output") : tail) + "); see " + log;
  } else {
    check_itasc_outputs(scene, csv, report, pose, run);
  }
  if (!run.ok()) fs::remove(csv, ec);  // no figure shows an unchecked pose
  return run;
}

}  // namespace physik::experiments
