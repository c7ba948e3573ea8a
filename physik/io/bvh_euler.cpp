// Euler angles in a BVH channel order, both ways, and the closest of equivalent triples to the
// previous frame's (bvh.h).
#include "physik/io/bvh.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <limits>
#include <sstream>

#include "physik/io/bvh_detail.h"

namespace physik {

using bvh_detail::axis_index;
using bvh_detail::check_order;
using bvh_detail::upper;

// ---------------------------------------------------------------- Euler angles

Quat rotation_from_euler(const Vec3& angles, const std::string& order) {
  check_order(order);
  Quat q = Quat::Identity();
  for (int k = 0; k < 3; ++k) {
    q = q * Eigen::AngleAxisd(angles[k], Vec3::Unit(axis_index(std::toupper(order[k]))));
  }
  return q;
}

Vec3 euler_from_rotation(const Quat& q, const std::string& order) {
  check_order(order);
  // R = R_i(a) R_j(b) R_k(c); s = +1 for cyclic orders (XYZ, YZX, ZXY), -1 otherwise
  const int i = axis_index(std::toupper(order[0]));
  const int j = axis_index(std::toupper(order[1]));
  const int k = axis_index(std::toupper(order[2]));
  const double s = j == (i + 1) % 3 ? 1.0 : -1.0;
  const Mat3 m = q.normalized().toRotationMatrix();
  // cos b from the two other entries of row i: M(i,i) = cos b cos c, M(i,j) = -s cos b sin c
  const double cb = std::hypot(m(i, i), m(i, j));
  const double b = std::atan2(s * m(i, k), cb);
  double a, c;
  if (cb > 1e-9) {
    a = std::atan2(-s * m(j, k), m(k, k));
    c = std::atan2(-s * m(i, j), m(i, i));
  } else {
    // gimbal lock: only a + c (or a - c) is defined; put it all in a
    c = 0.0;
    const Mat3 mi = m * Eigen::AngleAxisd(b, Vec3::Unit(j)).toRotationMatrix().transpose();
    a = std::atan2(mi((i + 2) % 3, (i + 1) % 3), mi((i + 1) % 3, (i + 1) % 3));
  }
  return Vec3(a, b, c);
}

namespace {

// v plus the whole turns that bring it nearest ref
double wrap_near(double v, double ref) {
  return v + 2.0 * kPi * std::round((ref - v) / (2.0 * kPi));
}

}  // namespace

// the equivalent Euler triple closest to `prev` (the other branch (a+pi, pi-b, c+pi) and 2 pi
// turns)
Vec3 bvh_detail::closest_euler(const Vec3& e, const Vec3& prev) {
  Vec3 best = e;
  double best_d = std::numeric_limits<double>::infinity();
  for (const Vec3& cand : {e, Vec3(e[0] + kPi, kPi - e[1], e[2] + kPi)}) {
    Vec3 w;
    for (int k = 0; k < 3; ++k) w[k] = wrap_near(cand[k], prev[k]);
    const double d = (w - prev).cwiseAbs().sum();
    if (d < best_d) {
      best_d = d;
      best = w;
    }
  }
  return best;
}

// R = R_i(a) R_j(b) R_k(c). Away from gimbal lock the closest triple is exact to round-off over
// cos b. At the lock only a + s c is defined, so c is taken as ref's and M = R R_k(-c) = R_i(a)
// R_j(b) gives a from its column j (R_i(a) e_j = cos a e_j + s sin a e_k) and b from its row i
// (e_i^T R_j(b): cos b at i, s sin b at k), s = +1 for cyclic orders
Vec3 nearest_euler(const Quat& q, const std::string& order, const Vec3& ref) {
  const Vec3 e = bvh_detail::closest_euler(euler_from_rotation(q, order), ref);
  if (std::abs(std::cos(e[1])) >= 1e-3) return e;
  const int i = axis_index(std::toupper(order[0]));
  const int j = axis_index(std::toupper(order[1]));
  const int k = axis_index(std::toupper(order[2]));
  const double s = j == (i + 1) % 3 ? 1.0 : -1.0;
  const Mat3 m = (q.normalized() * Eigen::AngleAxisd(-ref[2], Vec3::Unit(k))).toRotationMatrix();
  const double a = std::atan2(s * m(k, j), m(j, j));
  const double b = std::atan2(s * m(i, k), m(i, i));
  return Vec3(wrap_near(a, ref[0]), wrap_near(b, ref[1]), ref[2]);
}

}  // namespace physik
