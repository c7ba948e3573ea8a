// The coil's chain and scenes (coil.h).
#include "experiments/coil.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "physik/model/params.h"

namespace physik::experiments {

namespace {

using Curve = std::function<Vec3(double)>;  // rig units, of a parameter theta (rad)

// n + 1 points along the curve from theta = 0, each a chord of kCoilBoneLength from the last:
// the step in theta starts from the previous one and is scaled by L / chord until it fits
std::vector<Vec3> chord_points(const Curve& curve, int n) {
  std::vector<Vec3> p{curve(0.0)};
  double theta = 0.0, dtheta = 1e-3;
  for (int i = 0; i < n; ++i) {
    for (int k = 0; k < 20; ++k) {
      const double chord = (curve(theta + dtheta) - p.back()).norm();
      dtheta *= kCoilBoneLength / chord;
      if (std::abs(chord - kCoilBoneLength) < 1e-12 * kCoilBoneLength) break;
    }
    theta += dtheta;
    p.push_back(curve(theta));
  }
  return p;
}

// the chain through the points, in that shape at rest (coil.h)
Rig chain_through(const std::vector<Vec3>& p, const std::string& name) {
  std::vector<BoneSpec> specs(p.size() - 1);
  for (std::size_t i = 0; i < specs.size(); ++i) {
    BoneSpec& s = specs[i];
    s.name = "b" + std::to_string(i);
    s.parent = i == 0 ? "" : "b" + std::to_string(i - 1);
    s.head_world = p[i];
    s.tail_world = p[i + 1];
    s.rest_frame_world = rest_frame_from_roll(s.head_world, s.tail_world, 0.0);
    s.mass = 1.0 * kCoilBoneLength;  // kg, 1 kg per rig unit
    s.radius = kCoilRadius;
    s.collision_radius = kCoilRadius;
  }
  return build_rig(specs, "<" + name + ">", name);
}

// the inward sag of a chord L of a turn of radius rho, L^2 / (8 rho) (coil.h)
double chord_sag(double rho) {
  return kCoilBoneLength * kCoilBoneLength / (8.0 * rho);
}

Scene coil_scene(const Rig& rig, const std::string& name, bool contacts, int steps) {
  Scene s;
  s.file = "<" + name + ">";
  s.rig = rig;
  s.params = preset_params("robust");
  s.params.dt = 0.01;
  s.params.damping = kCoilDamping;
  s.params.damping_auto = false;
  s.params_given = {"preset", "dt", "damping"};
  s.steps = steps;
  s.initial_pose = rest_pose(rig);
  s.gravity_world = Vec3(0, 0, -9.81);
  if (contacts) {
    s.collision.ground = GroundPlane{};
    s.collision.self_collision = true;
  }
  return s;
}

// the flat spiral from inner radius rho0 with turns `pitch` apart, rig units (coil.h)
Curve flat_spiral(double rho0, double pitch) {
  const double e = kCoilRadius / 25.0;
  return [=](double theta) {
    const double rho = rho0 + pitch * theta / (2.0 * kPi);
    return Vec3(rho * std::cos(theta), rho * std::sin(theta), kCoilRadius - e);
  };
}

}  // namespace

Scene coil_flat_spiral_scene(int nbone, bool contacts, int steps) {
  const std::string name = "coil flat spiral " + std::to_string(nbone);
  const double rho0 = 3.0 * kCoilBoneLength, e = kCoilRadius / 25.0;
  const Curve spiral = flat_spiral(rho0, 2.0 * kCoilRadius - e + chord_sag(rho0));
  return coil_scene(chain_through(chord_points(spiral, nbone), name), name, contacts, steps);
}

Scene coil_flat_ring_scene(int nbone, int turns, bool contacts, int steps) {
  if (turns < 1) throw std::invalid_argument("coil_flat_ring_scene: turns must be at least 1");
  // the length of `turns` turns from rho0 is about 2 pi turns rho0 + pi s turns^2: solve for rho0
  // (the pitch s depends on rho0 only through the sag, a few fixed-point passes)
  const double e = kCoilRadius / 25.0;
  double rho0 = 3.0 * kCoilBoneLength, pitch = 0.0;
  for (int k = 0; k < 5; ++k) {
    pitch = 2.0 * kCoilRadius + e + chord_sag(rho0);
    const double fit =
        (nbone * kCoilBoneLength - kPi * pitch * turns * turns) / (2.0 * kPi * turns);
    rho0 = std::max(3.0 * kCoilBoneLength, fit);
  }
  pitch = 2.0 * kCoilRadius + e + chord_sag(rho0);
  const std::string name = "coil flat ring " + std::to_string(nbone);
  return coil_scene(chain_through(chord_points(flat_spiral(rho0, pitch), nbone), name), name,
                    contacts, steps);
}

Scene coil_helix_scene(int nbone, int turns, int steps) {
  const double radius = nbone * kCoilBoneLength / (2.0 * kPi * turns);
  const double pitch = 3.0 * kCoilRadius;
  const Curve helix = [&](double theta) {
    return Vec3(radius * std::cos(theta), radius * std::sin(theta),
                2.0 * kCoilRadius + pitch * theta / (2.0 * kPi));
  };
  const std::string name = "coil helix " + std::to_string(nbone);
  return coil_scene(chain_through(chord_points(helix, nbone), name), name, true, steps);
}

double candidate_pairs_per_bone(const Scene& scene, const BoneFrames& f) {
  const int n = scene.rig.nbone;
  std::vector<Eigen::AlignedBox3d> box(n);
  for (int i = 0; i < n; ++i) {
    const Vec3 r = Vec3::Constant(scene.rig.bone_collision_radius[i]);
    box[i] = Eigen::AlignedBox3d(f.head_world[i].cwiseMin(f.tail_world[i]) - r,
                                 f.head_world[i].cwiseMax(f.tail_world[i]) + r);
  }
  long count = 0;
  for (int a = 0; a < n; ++a) {
    for (int b = a + 1; b < n; ++b) {
      if (!scene.rig.bones_share_joint(a, b) && box[a].intersects(box[b])) ++count;
    }
  }
  return static_cast<double>(count) / n;
}

}  // namespace physik::experiments
