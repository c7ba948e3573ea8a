// Clip: a BVH or qBVH animation in Python (physik/io/bvh.h BvhFile): its skeleton, its frames
// as a numpy array, read and written; a clip's frame as a rig's pose (source_clip_pose) and a
// rig's poses as a clip of its source skeleton (the write-back, source_clip_of_poses, keeping
// from the source frames what the rig cannot hold); the rig of a clip (`rig from-bvh`), the rig's
// source skeleton, and the scene that follows a clip (`physik follow`, clip_follow.h). The
// pure-Python half (python/physik/__init__.py) wraps poses and runs a follow.
#include <cmath>
#include <fstream>
#include <sstream>
#include <tuple>
#include <utility>

#include <pybind11/stl.h>

#include "physik/io/bvh.h"
#include "physik/io/clip_follow.h"
#include "physik/io/output_files.h"
#include "physik/io/rig_io.h"
#include "physik/io/scene_io.h"
#include "physik/io/source_skeleton_io.h"
#include "physik/model/errors.h"
#include "python/bind_common.h"

namespace physik::python {

namespace {

// rows x cols doubles as a new array
py::array matrix(const std::vector<std::vector<double>>& rows, py::ssize_t cols) {
  py::array_t<double> a({static_cast<py::ssize_t>(rows.size()), cols});
  auto m = a.mutable_unchecked<2>();
  for (std::size_t i = 0; i < rows.size(); ++i) {
    for (py::ssize_t k = 0; k < cols; ++k) m(i, k) = rows[i][k];
  }
  return a;
}

// clip.frames = array: (nframe, nchannel) numbers, checked as a file's frames are
void set_frames(BvhFile& clip, py::object value) {
  const py::array_t<double, py::array::c_style | py::array::forcecast> a(value);
  if (a.ndim() != 2 || a.shape(1) != clip.nchannel) {
    throw_input_error("frames", "", "shape",
                      "expected (nframe, " + std::to_string(clip.nchannel) +
                          "), one column per "
                          "channel");
  }
  BvhFile next = clip;
  next.frames.assign(a.shape(0), std::vector<double>(clip.nchannel));
  auto m = a.unchecked<2>();
  for (py::ssize_t f = 0; f < a.shape(0); ++f) {
    for (py::ssize_t k = 0; k < a.shape(1); ++k) next.frames[f][k] = m(f, k);
  }
  check_bvh_frames(next, "frames");
  clip = std::move(next);
}

// the clip as physik writes a file: refused (nothing written) where physik could not read it
void write_clip(const BvhFile& clip, const std::string& path) {
  BvhFile checked = clip;
  check_bvh_frames(checked, path);
  std::ostringstream text;
  write_bvh_file(checked, path, text);
  std::ofstream out = open_output_file(path, "");
  out << text.str();
  if (!out) throw_input_error(path, "", "", "write failed");
}

// (nframe x nbone x 4) local rotations (x, y, z, w) and (nframe x 3) root heads as poses
std::vector<Pose> poses_of(const Rig& rig, py::object local_rotations, py::object root_heads) {
  const py::array_t<double, py::array::c_style | py::array::forcecast> q(local_rotations);
  const py::array_t<double, py::array::c_style | py::array::forcecast> r(root_heads);
  if (q.ndim() != 3 || q.shape(1) != rig.nbone || q.shape(2) != 4 || r.ndim() != 2 ||
      r.shape(1) != 3 || r.shape(0) != q.shape(0)) {
    throw_input_error("poses", "", "shape",
                      "expected poses of " + std::to_string(rig.nbone) +
                          " local rotations (x, y, z, w) and a root head each");
  }
  std::vector<Pose> poses(q.shape(0));
  auto qm = q.unchecked<3>();
  auto rm = r.unchecked<2>();
  for (py::ssize_t f = 0; f < q.shape(0); ++f) {
    Pose& p = poses[f];
    p.root_head_world = Vec3(rm(f, 0), rm(f, 1), rm(f, 2));
    p.bone_local_rotation.resize(rig.nbone);
    for (int b = 0; b < rig.nbone; ++b) {
      const Quat v(qm(f, b, 3), qm(f, b, 0), qm(f, b, 1), qm(f, b, 2));
      if (!v.coeffs().allFinite() || std::abs(v.norm() - 1.0) > 1e-6 ||
          !p.root_head_world.allFinite()) {
        throw_input_error("poses", "pose " + std::to_string(f), "bone '" + rig.bone_name[b] + "'",
                          "not a finite unit quaternion and root head");
      }
      p.bone_local_rotation[b] = v.normalized();
    }
  }
  return poses;
}

// a clip of `rig`'s source skeleton (checked) for the write-back's source frames
void check_source_clip(const Rig& rig, const BvhFile& clip, const std::string& what) {
  if (rig.source_skeleton.empty()) {
    throw_input_error(what, "", "rig",
                      "the rig has no source skeleton (a rig made by Rig.from_bvh or `physik rig "
                      "from-bvh` has one)");
  }
  const std::string mismatch = source_skeleton_mismatch(rig.source_skeleton, clip);
  if (!mismatch.empty()) {
    throw_input_error(what, "", "clip", "not a clip of the rig's source skeleton: " + mismatch);
  }
}

void bind_clip_class(py::module_& m);

}  // namespace

void bind_clip(py::module_& m) {
  bind_clip_class(m);
  m.def(
      "_clip_of_poses",
      [](const Rig& rig, py::object local_rotations, py::object root_heads, double frame_time,
         const BvhFile* source, std::vector<int> source_frames, bool quaternion,
         const std::string& euler_order, bool own_skeleton) {
        const std::vector<Pose> poses = poses_of(rig, local_rotations, root_heads);
        BvhExportOptions o;
        o.frame_time = frame_time;
        o.quaternion = quaternion;
        o.euler_order = euler_order;
        o.source_skeleton = !own_skeleton;
        o.target = "Clip.of_poses";
        SourceFrames held;
        if (source) {
          check_source_clip(rig, *source, "Clip.of_poses");
          held.rows = source->frames;
          for (int f : source_frames) {
            if (f >= static_cast<int>(held.rows.size())) {
              throw_input_error("Clip.of_poses", "", "source_frames",
                                "frame " + std::to_string(f) + " is past the source clip's end");
            }
          }
          held.frame_of_pose = source_frames;
        }
        std::ostringstream text;
        const BvhWriteReport report = write_bvh(rig, poses, o, text, held);
        return py::make_tuple(parse_bvh(text.str(), "Clip.of_poses"), report.warnings);
      },
      py::arg("rig"), py::arg("local_rotations"), py::arg("root_heads"), py::arg("frame_time"),
      py::arg("source").none(true), py::arg("source_frames"), py::arg("quaternion"),
      py::arg("euler_order"), py::arg("own_skeleton"),
      "Clip.of_poses's C++ half: (clip, warnings).");
  m.def(
      "_follow_scene",
      [](const BvhFile& clip, const Rig& rig, std::vector<std::pair<std::string, double>> pts,
         int first, int last, std::optional<double> ground, bool gravity, py::object params) {
        FollowOptions o;
        for (const auto& [bone, alpha] : pts) o.points.push_back({bone, alpha});
        std::tie(o.first, o.last) = std::make_pair(first, last);
        if (ground && !(std::isfinite(*ground) && std::abs(*ground) <= kMaxCoordinate)) {
          throw_input_error("ground", "", "", "must be a finite height within +-1e9 rig units");
        }
        o.ground = ground;
        o.gravity = gravity;
        o.source = "follow";
        if (first < 0) throw_input_error("frames", "", "", "frame numbers start at 0");
        const ParamOverrides given = param_overrides(params, "params");
        return follow_scene(rig, clip, follow_params(rig, clip, o, given), o);
      },
      py::arg("clip"), py::arg("rig"), py::arg("points"), py::arg("first"), py::arg("last"),
      py::arg("ground").none(true), py::arg("gravity"), py::arg("params").none(true),
      "follow_scene's C++ half.");
  m.def("_followed_frame", &followed_frame, py::arg("scene"), py::arg("step"),
        "The clip frame (from the first followed) that a follow scene's state after `step` steps "
        "stands for, -1 between them (clip_follow.h followed_frame).");
  m.def("_follow_frame_time", &follow_frame_time, py::arg("scene"),
        "The engine's time per clip frame of a follow scene, s (clip_follow.h).");
}

namespace {

// the clip's skeleton, read only
void bind_clip_skeleton(py::class_<BvhFile>& cls) {
  cls.def_property_readonly(
         "joint_names",
         [](const BvhFile& c) {
           std::vector<std::string> out;
           for (const BvhJoint& j : c.joints) out.push_back(j.name);
           return out;
         },
         "Joint names, in file order (parents first).")
      .def_property_readonly(
          "joint_parents",
          [](const BvhFile& c) {
            std::vector<int> out;
            for (const BvhJoint& j : c.joints) out.push_back(j.parent);
            return out;
          },
          "Each joint's parent index (-1 for the root).")
      .def_property_readonly(
          "offsets",
          [](const BvhFile& c) {
            std::vector<Vec3> out;
            for (const BvhJoint& j : c.joints) out.push_back(j.offset);
            return vec3_array(out);
          },
          "(njoint, 3) OFFSETs, file units, in each parent's frame.")
      .def_property_readonly(
          "end_sites",
          [](const BvhFile& c) {
            py::list out;
            for (const BvhJoint& j : c.joints) out.append(vec3_array(j.end_sites));
            return out;
          },
          "Per joint, its End Sites as a (k, 3) array, file units.")
      .def_property_readonly(
          "channels",
          [](const BvhFile& c) {
            std::vector<std::vector<std::string>> out;
            for (const BvhJoint& j : c.joints) {
              out.emplace_back();
              for (BvhChannel ch : j.channels) out.back().push_back(bvh_channel_name(ch));
            }
            return out;
          },
          "Per joint, its channel names in file order.")
      .def_property_readonly(
          "columns",
          [](const BvhFile& c) {
            std::vector<std::string> out;
            for (const BvhJoint& j : c.joints) {
              for (BvhChannel ch : j.channels) out.push_back(j.name + ":" + bvh_channel_name(ch));
            }
            return out;
          },
          "The name of every column of frames, \"joint:Channel\".");
}

// a frame as the rig's pose, and the Python protocol
void bind_clip_poses(py::class_<BvhFile>& cls) {
  cls.def(
         "_pose",
         [](const BvhFile& c, const Rig& rig, int frame) {
           check_source_clip(rig, c, "Clip.pose");
           if (frame < 0 || frame >= static_cast<int>(c.frames.size())) {
             throw_input_error("Clip.pose", "", "frame",
                               "frame " + std::to_string(frame) + " is outside 0.." +
                                   std::to_string(static_cast<int>(c.frames.size()) - 1));
           }
           BoneFrames scratch;
           Pose pose;
           source_clip_pose(rig, c, frame, scratch, pose);
           // a clip's pose has no scene: its angles in the default scheme's joints (implicit)
           return pose_arrays(rig, EngineParams{}.locked_axes(), forward_kinematics(rig, pose),
                              pose);
         },
         py::arg("rig"), py::arg("frame"), "Clip.pose's C++ half: the pose's arrays.")
      .def(
          "copy", [](const BvhFile& c) { return BvhFile(c); }, "An independent copy.")
      .def("__len__", [](const BvhFile& c) { return c.frames.size(); })
      .def("__repr__", [](const BvhFile& c) {
        return "<physik.Clip of " + std::to_string(c.joints.size()) + " joints, " +
               std::to_string(c.frames.size()) + " frames>";
      });
}

void bind_clip_class(py::module_& m) {
  py::class_<BvhFile> cls(m, "Clip", R"doc(A BVH or qBVH animation: a skeleton and its frames.

Clip.load(path) reads a file as the CLI does (bad input raises InputError naming the file and
line); clip.frames is a (nframe, nchannel) array (a copy; assign a new array to change them,
checked as a file's frames are), one column per channel in file order (clip.columns names
them): degrees, file units, quaternions (w, x, y, z). clip.write(path) writes it as it is.
clip.pose(rig, frame) is the rig's pose of a frame (a clip of the rig's source skeleton);
Clip.of_poses(rig, poses, ...) the other way.)doc");
  cls.def_static("load", &read_bvh_file, py::arg("path"), "Read a BVH or qBVH file.")
      .def_static(
          "parse",
          [](const std::string& text, const std::string& source) {
            return parse_bvh(text, source);
          },
          py::arg("text"), py::arg("source") = "<text>",
          "A clip from BVH text; `source` names it in error messages.")
      .def("write", &write_clip, py::arg("path"),
           "Write the clip to `path` as it is (its own channels; folders are created). A value "
           "physik's reader would refuse (beyond +-1e9) raises InputError and writes nothing.")
      .def_property(
          "frames", [](const BvhFile& c) { return matrix(c.frames, c.nchannel); }, &set_frames,
          "(nframe, nchannel) channel values, a copy; assigning an array replaces them (checked).")
      .def_property(
          "frame_time", [](const BvhFile& c) { return c.frame_time; },
          [](BvhFile& c, double t) {
            if (!(t > 0.0) || !std::isfinite(t)) {
              throw_input_error("frame_time", "", "", "must be a positive finite number (s)");
            }
            c.frame_time = t;
          },
          "Seconds per frame.")
      .def_property_readonly(
          "nframe", [](const BvhFile& c) { return c.frames.size(); }, "Number of frames.")
      .def_readonly("nchannel", &BvhFile::nchannel, "Number of channels (columns of frames).");
  bind_clip_skeleton(cls);
  bind_clip_poses(cls);
}

// Rig.from_bvh: `physik rig from-bvh FILE --scale S --axes A --root R`, of a path or a Clip
Rig rig_from_bvh(py::object clip, double scale, const std::string& axes, py::object root) {
  BvhImportOptions o;
  if (axes != "y-up" && axes != "z-up") {
    throw_input_error("axes", "", "", "expected y-up or z-up, got '" + axes + "'");
  }
  o.axes = axes == "z-up" ? BvhAxes::kZUp : BvhAxes::kYUp;
  if (!(scale > 0.0) || !std::isfinite(scale)) {
    throw_input_error("scale", "", "", "must be a positive finite number");
  }
  o.scale = scale;
  if (!root.is_none()) {
    const std::string r = root.cast<std::string>();
    if (r != "free" && r != "pinned") {
      throw_input_error("root", "", "", "expected free or pinned, got '" + r + "'");
    }
    o.root = r == "free" ? RootJoint::kFree : RootJoint::kPinned;
  }
  if (py::isinstance<BvhFile>(clip)) return bvh_to_rig(clip.cast<BvhFile>(), "clip", o).pivots.rig;
  return load_bvh(clip.cast<std::string>(), o).pivots.rig;
}

}  // namespace

void bind_rig_source(py::class_<Rig>& cls) {
  cls.def_static(
         "from_bvh", &rig_from_bvh, py::arg("clip"), py::arg("scale") = 1.0,
         py::arg("axes") = "y-up", py::arg("root") = py::none(),
         R"doc(The rig of a BVH/qBVH file or a Clip: `physik rig from-bvh FILE --scale S --axes A
--root R` (its warnings and notes are in rig.source_notes). root: "free", "pinned" or None (pinned
when the file's root has no position channels). The rig keeps the file's skeleton
(rig.source_skeleton), so Clip.pose and Clip.of_poses go between the two.)doc")
      .def_property_readonly(
          "source_skeleton",
          [](const Rig& r) -> py::object {
            if (r.source_skeleton.empty()) return py::none();
            return from_json(source_skeleton_to_json(r));
          },
          "The skeleton the rig was converted from (the rig file's \"source_skeleton\": joints, "
          "channels, offsets, axes, scale, the bones of each joint), or None.")
      .def_readonly("source_notes", &Rig::source,
                    "The rig file's \"source\" notes: where it came from, what a converter chose "
                    "and warned about.")
      .def_property_readonly(
          "root", [](const Rig& r) { return std::string(to_string(r.root_joint)); },
          "The root's joint to the world: \"free\", \"pinned\" or \"fixed\".");
}

}  // namespace physik::python
