// Bounds on the values a user gives that no rig holds (beside rig.h's kMaxCoordinate, kMinScale
// and kMaxScale): each reader refuses a value past them with InputError (exit 2).
#pragma once

namespace physik {

// degrees, any angle a file gives (a BVH rotation channel, a scene's rotation_deg): beyond it a
// turn's sine and cosine have lost every digit, and past 1e305 deg2rad's product overflows
constexpr double kMaxAngleDeg = 1e6;

// how far from 1 the norm of a quaternion a user gives may be (a qBVH channel set, a scene's or
// an option's orientation target): within it the quaternion is normalised, beyond it refused. A
// value a person types, [0.7071, 0.7071, 0, 0], has norm 0.99999.
constexpr double kQuaternionNormTol = 1e-3;

}  // namespace physik
