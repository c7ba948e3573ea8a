#include "physik/engine/implicit_elements.h"

namespace physik {

void add_point_inertia(const Mat3& A, const Vec3& r, SpatialInertia& I) {
  const Mat3 RA = skew(r) * A;  // [r]x A
  I.A.noalias() += RA * skew(r).transpose();
  I.B += RA;
  I.C += A;
}

void add_point_element(const Mat3& A, const Vec3& r, const Vec6& a0, SpatialInertia& inertia,
                       Vec6& bias) {
  add_point_inertia(A, r, inertia);
  // -Phi^T A Phi a0 into the body's bias force: the element force's velocity-product share
  const Vec3 f = A * (a0.tail<3>() + a0.head<3>().cross(r));  // A times the point's a0
  bias.head<3>() -= r.cross(f);
  bias.tail<3>() -= f;
}

void add_couple_element(const Mat3& A, const Vec6& a0, SpatialInertia& inertia, Vec6& bias) {
  inertia.A += A;
  bias.head<3>() -= A * a0.head<3>();
}

void add_couple_point_element(const Mat3& A, const Vec3& r, const Vec6& a0, SpatialInertia& inertia,
                              Vec6& bias) {
  // [[-A [r]x + [r]x A^T, A]; [A^T, 0]]
  inertia.A += skew(r) * A.transpose() - A * skew(r);
  inertia.B += A;
  const Vec3 point_a0 = a0.tail<3>() + a0.head<3>().cross(r);  // Phi a0
  const Vec3 f = A.transpose() * a0.head<3>();
  bias.head<3>() -= A * point_a0 + r.cross(f);
  bias.tail<3>() -= f;
}

}  // namespace physik
