// The implicit step (physik/engine/implicit_step.h): the one-DOF spring-damper recurrence against
// its closed form for every h, c, k > 0; energy never grows on linear cases; the capped and torsion
// tangents against finite differences; the augmented-inertia recursion against a dense
// (M + h D + h^2 K) a = tau - C - h K v with K and D built from finite differences of the force
// laws and point Jacobians, on random trees; no allocation per step is in engine_alloc_test.
#include "physik/engine/implicit_step.h"

#include <cmath>
#include <complex>
#include <iostream>
#include <random>
#include <type_traits>

#include <gtest/gtest.h>

#include "physik/engine/control_springs.h"
#include "physik/engine/engine.h"
#include "physik/engine/forces.h"
#include "physik/engine/integrate_joint_space.h"
#include "physik/engine/potential.h"
#include "physik/engine/torsion_springs.h"
#include "physik/ik/ik_solver.h"
#include "physik/io/rig_io.h"
#include "tests/dense_dynamics.h"
#include "tests/engine_test_util.h"
#include "tests/test_util.h"

namespace physik {
namespace {

using dense::MatX;
using dense::VecX;

// A rod translating on a spring at its centre with dampers at both ends: m x'' = -k x - 2 c x'.
Scene rod_scene(double h, double c, double k, const Vec3& offset, const Vec3& v0) {
  EngineParams p = test::bare_params(h);
  p.scheme = Scheme::kImplicit;
  p.damping = c;
  Scene s = test::scene_for(test::one_rod(2.0, 1.7), p, 60);
  s.control_points = {test::control(0, 0.5, Vec3(0, 0, 1) - offset, k)};
  s.initial_velocity_world = v0;
  return s;
}

// the closed form of the recurrence (implicit_step.h): [x+; v+] = A [x; v]
Eigen::Matrix2d recurrence(double m, double h, double c, double k) {
  const double S = m + h * c + h * h * k;
  Eigen::Matrix2d A;
  A << m + h * c, h * m, -h * k, m;
  return A / S;
}

TEST(ImplicitStep, OneDofRecurrenceMatchesItsClosedFormAndIsStableForEveryStep) {
  const double m = 1.7;
  for (double h : {1e-3, 0.05, 1.0, 100.0}) {
    for (double c : {1e-3, 3.0, 1000.0}) {
      for (double k : {0.1, 10.0, 1e4}) {
        const Scene s = rod_scene(h, c, k, Vec3(0.7, 0, 0), Vec3(0, 0, 0));
        SimState st;
        init_state(s, st);
        const Eigen::Matrix2d A = recurrence(m, h, c + c, k);  // two end dampers
        // eigenvalues of the closed form: inside the unit circle
        const double tr = A.trace(), det = A.determinant();
        const std::complex<double> disc = std::sqrt(std::complex<double>(tr * tr - 4 * det));
        const double rho = std::max(std::abs(0.5 * (tr + disc)), std::abs(0.5 * (tr - disc)));
        EXPECT_LT(rho, 1.0) << "h " << h << " c " << c << " k " << k;
        EXPECT_NEAR(det, m / (m + 2 * h * c + h * h * k), 1e-15);
        Eigen::Vector2d xv(0.7, 0.0);
        for (int n = 0; n < 60; ++n) {
          step(s, st);
          xv = A * xv;
          const double x = st.com_world[0].x() - s.control_points[0].target_world.x();
          ASSERT_NEAR(x, xv[0], 1e-12 * (1.0 + std::abs(xv[0])) + 1e-14)
              << "step " << n << " h " << h << " c " << c << " k " << k;
          ASSERT_NEAR(st.vel_world[0].x(), xv[1], 1e-11 * (1.0 + std::abs(xv[1])) + 1e-14);
          ASSERT_TRUE(st.omega_world[0].norm() < 1e-12);
        }
      }
    }
  }
}

TEST(ImplicitStep, EnergyNeverGrowsOnLinearCases) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> lg(-3.0, 3.0), u(-1.0, 1.0);
  for (int trial = 0; trial < 60; ++trial) {
    const double h = std::pow(10.0, lg(rng)), c = std::pow(10.0, lg(rng)),
                 k = std::pow(10.0, lg(rng));
    const Vec3 offset(u(rng), u(rng), u(rng)), v0(u(rng), u(rng), u(rng));
    const Scene s = rod_scene(h, c, k, offset, 3.0 * v0);
    SimState st;
    init_state(s, st);
    const Vec3 target = s.control_points[0].target_world;
    const auto energy = [&] {
      return kinetic_energy(s.rig, st) + 0.5 * k * (st.com_world[0] - target).squaredNorm();
    };
    double e = energy();
    const double round_off = 1e-13 * e;  // J: position round-off once the energy has decayed
    for (int n = 0; n < 40; ++n) {
      step(s, st);
      const double e_next = energy();
      ASSERT_LE(e_next, e + round_off) << "h " << h << " c " << c << " k " << k << " step " << n;
      e = e_next;
    }
  }
}

TEST(ImplicitStep, CappedTangentEqualsFiniteDifferences) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-2.0, 2.0);
  const double eps = 1e-6;
  for (int trial = 0; trial < 200; ++trial) {
    const SpringLaw law = trial % 2 ? SpringLaw::kCapped : SpringLaw::kLinear;
    const double k = 0.1 + std::abs(u(rng)) * 20.0, cap = 0.05 + std::abs(u(rng));
    const Vec3 d(u(rng), u(rng), u(rng));
    if (std::abs(d.norm() - cap) < 1e-3) continue;  // the kink of the capped law
    const Mat3 K = spring_tangent(law, k, cap, d);
    Mat3 fd;
    for (int j = 0; j < 3; ++j) {
      const Vec3 e = eps * Vec3::Unit(j);
      fd.col(j) = (spring_force(law, k, cap, d + e) - spring_force(law, k, cap, d - e)) / (2 * eps);
    }
    EXPECT_LT((K - fd).norm(), 1e-7 * k) << "law " << to_string(law) << " |d| " << d.norm();
    EXPECT_LT((K - K.transpose()).norm(), 1e-14 * k);
    EXPECT_GE(Eigen::SelfAdjointEigenSolver<Mat3>(K).eigenvalues().minCoeff(), -1e-12 * k);
  }
}

// The step's stiffness beyond the cap (spring_step_stiffness, torsion_step_stiffness_local) makes
// the quadratic model of the potential lie above it everywhere: U(x) <= U(d) + F(d).(x - d) +
// (x - d)^T K (x - d) / 2 for every x (F = dU/dd, d = t - a), equality at x = d. The tangent alone
// does not (the model is linear along the pull and falls below U past the target).
TEST(ImplicitStep, CappedStepStiffnessMajorisesThePotential) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-3.0, 3.0);
  int tangent_below = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    const SpringLaw law = trial % 4 ? SpringLaw::kCapped : SpringLaw::kLinear;
    const double k = 0.1 + std::abs(u(rng)) * 20.0, cap = 0.05 + 0.3 * std::abs(u(rng));
    const Vec3 d(u(rng), u(rng), u(rng)), x(u(rng), u(rng), u(rng));
    const auto model = [&](const Mat3& K) {
      return control_spring_potential(law, k, cap, d.norm()) +
             spring_force(law, k, cap, d).dot(x - d) + 0.5 * (x - d).dot(K * (x - d));
    };
    const double U = control_spring_potential(law, k, cap, x.norm());
    EXPECT_GE(model(spring_step_stiffness(law, k, cap, d)), U - 1e-12 * (1.0 + U))
        << "law " << to_string(law) << " |d| " << d.norm() << " |x| " << x.norm() << " cap " << cap;
    tangent_below += model(spring_tangent(law, k, cap, d)) < U - 1e-9;
    // the torsion spring's per-axis law is the same function of the excess
    EngineParams p = preset_params("original");
    p.torsion_k = k;
    p.torsion_cap = cap;
    p.torsion_spring = law;
    p.torsion_tolerance = 0.0;
    const std::array<AxisLimit, 3> locked = {AxisLimit{true, 0.0, 0.0}, AxisLimit{false, 0.0, 0.0},
                                             AxisLimit{false, 0.0, 0.0}};
    const Vec3 th(d.x(), 0.0, 0.0), th1(x.x(), 0.0, 0.0);
    const double Kt = torsion_step_stiffness_local(locked, th, p)[0];
    const double mt = torsion_spring_potential(law, k, cap, -th.x()) -
                      torsion_torque_local(locked, th, p)[0] * (th1.x() - th.x()) +
                      0.5 * Kt * (th1.x() - th.x()) * (th1.x() - th.x());
    const double Ut = torsion_spring_potential(law, k, cap, -th1.x());
    EXPECT_GE(mt, Ut - 1e-12 * (1.0 + Ut))
        << "torsion, law " << to_string(law) << " theta " << th.x();
  }
  EXPECT_GT(tangent_below, 100);  // the test can tell the two apart
}

TEST(ImplicitStep, TorsionStiffnessEqualsFiniteDifferences) {
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(-1.5, 1.5);
  const double eps = 1e-7;
  for (int trial = 0; trial < 200; ++trial) {
    EngineParams p = preset_params("original");
    p.torsion_k = 7.0;
    p.torsion_spring = trial % 2 ? SpringLaw::kCapped : SpringLaw::kLinear;
    p.torsion_cap = 0.3;
    std::array<AxisLimit, 3> limits;
    for (int a = 0; a < 3; ++a) {
      const double lo = std::min(u(rng), 0.0), hi = lo + std::abs(u(rng)) * (a == 1 ? 0.0 : 1.0);
      limits[a] = {trial % 5 != a, lo, hi};  // some axes free, y locked
    }
    const Vec3 theta(u(rng), u(rng), u(rng));
    const Vec3 k = torsion_stiffness_local(limits, theta, p);
    for (int a = 0; a < 3; ++a) {
      const Vec3 e = eps * Vec3::Unit(a);
      const Vec3 fd = (torsion_torque_local(limits, theta + e, p) -
                       torsion_torque_local(limits, theta - e, p)) /
                      (2 * eps);
      if (std::abs(fd[a] + k[a]) > 1e-5) {
        // only at a kink (the band edge or the cap) may the two differ
        const Vec3 fd1 = (torsion_torque_local(limits, theta + 1e3 * e, p) -
                          torsion_torque_local(limits, theta - 1e3 * e, p)) /
                         (2e3 * eps);
        ADD_FAILURE() << "axis " << a << " stiffness " << k[a] << " finite difference " << -fd[a]
                      << " (wider " << -fd1[a] << ")";
      }
      for (int b = 0; b < 3; ++b) {
        if (b != a) {
          EXPECT_NEAR(fd[b], 0.0, 1e-6);  // axes independent: a diagonal stiffness
        }
      }
    }
  }
}

// The torsion joint block against the torque's exact tangent in the rotation. With the parent
// held, turning the child by dphi (world axes) moves the ball's rotation vector by
// J_l^-1(theta) R_pr^T dphi (J_l^-1 = I - W/2 + b W^2, W = [theta]x; torsion_springs.h has its
// transpose), so the exact tangent of the world torque T tau_local(theta) is
//   -dtau/dphi = T diag(k) J_l^-1 R_pr^T + (T's own turn with theta) tau_local.
// The step's block (torsion_block_world, torsion_step_block_local):
//   the paper's torque (T = R_pr): T does not turn with theta, so the block is the exact tangent
//     less the negative part of its symmetric part, and it is not symmetric on a bent joint. On
//     the elbow bent 45 degrees about its hinge (k_y = k_z, theta along x; the pose below is 2e-4
//     rad off it, where the clip removes a part of order 1e-9, below the check's bound) its
//     antisymmetric part is -R_pr diag(k) (W / 2) R_pr^T, of norm sqrt(2) k |theta_x| / 2 (a
//     symmetric block dropped it: the beyond_the_paper large-steps rows took 22 steps at dt 1
//     with it, against 17 with the gradient torque);
//   gradient torque (T = R_pr J_l^-T): symmetric, the exact tangent up to the second term, the
//     torque's own size.
// Both blocks' symmetric parts are positive semi-definite.
// Two poses: the elbow's (y and z locked and just engaged, so the torque almost vanishes), and
// one off the hinge with only y locked (diag(k) and W do not commute there, so a block built
// with J_l^-1 in place of J_l^-T fails it).
struct BlockCase {
  Scene sc;
  SimState s;
};

// the elbow rig with its joint turned by theta (or off the hinge, z freed), tangents taken
BlockCase block_case(bool elbow, TorsionTorque torque, const Vec3& theta) {
  BlockCase c;
  c.sc.file = "<elbow>";
  // the forearm's locked axes held by springs (its hinge has no locked axis to engage)
  c.sc.rig = test::with_spring_locks(load_rig(test::model_path("rigs/elbow.json")));
  c.sc.params = preset_params("original");
  c.sc.params.scheme = Scheme::kImplicit;
  c.sc.params.torsion_torque = torque;
  if (!elbow) c.sc.rig.bone_limit[1][2].limited = false;  // z free: only y locked
  size_state(c.sc, c.s);
  c.s.pose = rest_pose(c.sc.rig);
  c.s.pose.bone_local_rotation[1] = quat_from_rotation_vector(theta);
  forward_kinematics(c.sc.rig, c.s.pose, c.s.frames);
  element_tangents(c.sc, c.s);
  return c;
}

// the torsion torque in world axes after a further turn dphi of the joint (world axes)
Vec3 turned_torque_world(const BlockCase& c, const Vec3& dphi_world) {
  const Quat parent = c.s.frames.orient_world[0];
  const Mat3 Rpr = (parent * c.sc.rig.bone_rest_orient_parent[1]).toRotationMatrix();
  const Quat q =
      quat_from_rotation_vector(Rpr.transpose() * dphi_world) * c.s.pose.bone_local_rotation[1];
  const Vec3 th = rotation_vector(q);
  return Vec3(torsion_torque_frame(c.sc.rig, c.sc.params, parent, 1, th) *
              torsion_torque_local(c.sc.rig.bone_limit[1], th, c.sc.params));
}

TEST(ImplicitStep, TorsionBlockIsTheTorquesTangent) {
  for (const bool elbow : {true, false}) {
    for (const TorsionTorque torque : {TorsionTorque::kAxes, TorsionTorque::kGradient}) {
      const Vec3 theta = elbow ? Vec3(-0.25 * kPi, 1e-4, -2e-4) : Vec3(-0.6, 1e-4, 0.5);
      BlockCase c = block_case(elbow, torque, theta);
      const Scene& sc = c.sc;
      SimState& s = c.s;
      const Mat3 block = torsion_block_world(sc.rig, s, 1);
      ASSERT_GT(block.norm(), 5.0) << "the locked axes engaged";
      const auto torque_world = [&](const Vec3& dphi) { return turned_torque_world(c, dphi); };
      // the test's torque is the engine's
      for (Vec3& t : s.torque_world) t.setZero();
      apply_torsion_springs(sc.rig, sc.params, s);
      const double tau = torque_world(Vec3::Zero()).norm();
      ASSERT_GT(tau, 0.0);
      EXPECT_LT((s.torque_world[1] - torque_world(Vec3::Zero())).norm(), 1e-12 * tau);

      const double eps = 1e-7;
      Mat3 exact;  // -dtau_world / dphi_world, by central differences
      for (int j = 0; j < 3; ++j) {
        exact.col(j) =
            -(torque_world(eps * Vec3::Unit(j)) - torque_world(-eps * Vec3::Unit(j))) / (2 * eps);
      }
      const std::string where =
          std::string(elbow ? "elbow" : "off the hinge") + ", " + to_string(torque);
      const Mat3 antisymmetric = 0.5 * (block - block.transpose());
      const Eigen::SelfAdjointEigenSolver<Mat3> block_sym(0.5 * (block + block.transpose()));
      EXPECT_GE(block_sym.eigenvalues().minCoeff(), -1e-12 * block.norm())
          << where << ": symmetric part PSD";
      if (torque == TorsionTorque::kGradient) {
        EXPECT_LT((exact - block).norm(), 2.0 * tau + 1e-6) << where << "\nexact\n"
                                                            << exact << "\nblock\n"
                                                            << block;
        EXPECT_LT(antisymmetric.norm(), 1e-12 * block.norm()) << where;
      } else {
        // no frame turns: the block is the tangent, to the differences' round-off, less the
        // negative part of its symmetric part (on the elbow ~1e-9, below the bound; off the hinge,
        // y alone engaged and theta not along y, the tangent's symmetric part is indefinite)
        const Eigen::SelfAdjointEigenSolver<Mat3> sym(0.5 * (exact + exact.transpose()));
        const Mat3 negative = sym.eigenvectors() * sym.eigenvalues().cwiseMin(0.0).asDiagonal() *
                              sym.eigenvectors().transpose();
        EXPECT_EQ(negative.norm() > 1e-3 * exact.norm(), !elbow)
            << where << ": " << sym.eigenvalues().transpose();
        EXPECT_LT((exact - negative - block).norm(), 1e-6 * block.norm()) << where << "\nexact\n"
                                                                          << exact << "\nblock\n"
                                                                          << block;
        EXPECT_LT((0.5 * (exact - exact.transpose()) - antisymmetric).norm(), 1e-6 * block.norm())
            << where;
        if (elbow) {
          const double expected = std::sqrt(2.0) * sc.params.torsion_k * std::abs(theta.x()) / 2.0;
          EXPECT_NEAR(antisymmetric.norm(), expected, 1e-3 * expected) << where;
        }
      }
    }
  }
}

// --- the recursion against a dense solve -----------------------------------------------------

struct Case {
  Scene scene;
  SimState s;
};

// a random tree with a random moving joint state, limits some of which are violated (engaged
// torsion springs), control points of both laws with random targets
Case random_case(std::mt19937& rng, int n, double h, double c, double f) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Case out;
  Scene& sc = out.scene;
  sc.file = "<random>";
  sc.rig = dense::random_limited_rig(rng, n);
  sc.params = preset_params("original");
  sc.params.scheme = Scheme::kImplicit;
  sc.params.dt = h;
  sc.params.damping = c;
  sc.params.angular_velocity_factor = f;
  sc.params.torsion_k = 13.0;
  sc.params.torsion_spring = n % 2 ? SpringLaw::kCapped : SpringLaw::kLinear;
  sc.params.torsion_cap = 0.4;
  sc.initial_pose = rest_pose(sc.rig);
  const int ncp = 1 + n / 2;
  for (int k = 0; k < ncp; ++k) {
    const int bone = std::uniform_int_distribution<int>(0, n - 1)(rng);
    sc.control_points.push_back(test::control(
        bone, 0.5 + 0.5 * u(rng), 2.0 * Vec3(u(rng), u(rng), u(rng)), 5.0 + 20.0 * std::abs(u(rng)),
        k % 2 ? SpringLaw::kCapped : SpringLaw::kLinear, 0.3));
  }
  SimState& s = out.s;
  size_state(sc, s);
  s.pose = rest_pose(sc.rig);
  forward_kinematics(sc.rig, s.pose, s.frames);
  init_joint_space(sc.rig, s);
  for (int i = 1; i < n; ++i) {
    s.pose.bone_local_rotation[i] = Quat(Eigen::AngleAxisd(1.5 * u(rng), dense::random_unit(rng)));
  }
  s.joint_space.root_com_world = Vec3(u(rng), u(rng), u(rng));
  s.joint_space.root_orient_world = Quat(Eigen::AngleAxisd(3.0 * u(rng), dense::random_unit(rng)));
  s.joint_space.root_vel_world = 2.0 * Vec3(u(rng), u(rng), u(rng));
  for (int i = 0; i < n; ++i) s.joint_space.joint_vel_local[i] = 2.0 * Vec3(u(rng), u(rng), u(rng));
  world_from_joint_space(sc.rig, s);
  for (std::size_t k = 0; k < sc.control_points.size(); ++k) {
    s.target_effective_world[k] = sc.control_points[k].target_world;
  }
  return out;
}

// the torsion spring's torque in world axes as a function of the ball's rotation vector
Vec3 torsion_world(const Scene& sc, const SimState& s, int i, const Vec3& theta) {
  const Quat Rpr = s.frames.orient_world[sc.rig.bone_parent[i]] * sc.rig.bone_rest_orient_parent[i];
  return Rpr * torsion_torque_local(sc.rig.bone_limit[i], theta, sc.params);
}

// K of the control springs from finite differences of the force laws, through the dense
// Jacobians (Gauss-Newton: J^T (-dF/dx) J)
MatX dense_control_K(const Scene& sc, const SimState& s, double eps) {
  const Rig& rig = sc.rig;
  MatX K = MatX::Zero(dense::nv(rig), dense::nv(rig));
  for (const ControlPoint& cp : sc.control_points) {
    const Vec3 a = point_on_bone(s.frames, cp.bone, cp.alpha);
    const Vec3 d = cp.target_world - a;
    Mat3 Kc;  // -dF/da by central differences
    for (int j = 0; j < 3; ++j) {
      const Vec3 e = eps * Vec3::Unit(j);
      Kc.col(j) = -(spring_force(*cp.spring, *cp.k, *cp.cap, d - e) -
                    spring_force(*cp.spring, *cp.k, *cp.cap, d + e)) /
                  (2 * eps);
    }
    Kc = 0.5 * (Kc + Kc.transpose());
    // beyond the cap the step adds the secant along the pull, where the tangent has none
    // (spring_step_stiffness): k c / |d| d^ d^T
    if (*cp.spring == SpringLaw::kCapped && d.norm() > *cp.cap) {
      Kc += (*cp.k * *cp.cap / d.norm()) * d.normalized() * d.normalized().transpose();
    }
    const MatX Jp = dense::point_jacobian(rig, s, cp.bone, a);
    K += Jp.transpose() * Kc * Jp;
  }
  return K;
}

// the torsion spring's block of bone b on the joint's relative turn (world axes), by finite
// differences: K_j = -dtau dtheta/dphi, with the capped secant and without negative eigenvalues
Mat3 dense_torsion_block(const Scene& sc, const SimState& s, int b, double eps) {
  const Rig& rig = sc.rig;
  const Vec3 theta = rotation_vector(s.pose.bone_local_rotation[b]);
  Mat3 dtau;  // d tau_world / d theta_local
  for (int j = 0; j < 3; ++j) {
    const Vec3 e = eps * Vec3::Unit(j);
    dtau.col(j) =
        (torsion_world(sc, s, b, theta + e) - torsion_world(sc, s, b, theta - e)) / (2 * eps);
  }
  // a capped torsion axis beyond its cap: the secant k c / |e| along its own axis
  // (torsion_step_stiffness_local), where the tangent has none
  const Mat3 Rpr = (s.frames.orient_world[rig.bone_parent[b]] * rig.bone_rest_orient_parent[b])
                       .toRotationMatrix();
  const EngineParams& prm = sc.params;
  if (prm.torsion_spring == SpringLaw::kCapped) {
    for (int a = 0; a < 3; ++a) {
      if (!rig.bone_limit[b][a].limited) continue;
      const double e = torsion_excess(rig.bone_limit[b][a], prm.torsion_tolerance, theta[a]);
      if (std::abs(e) > prm.torsion_cap) {
        dtau -= (prm.torsion_k * prm.torsion_cap / std::abs(e)) * Rpr.col(a) *
                Vec3::Unit(a).transpose();
      }
    }
  }
  // d theta / d phi: the ball's rotation vector under a relative turn phi (world axes), by
  // differences of the log map itself; not symmetric on a bent joint
  Mat3 dtheta;
  for (int j = 0; j < 3; ++j) {
    const Vec3 e = eps * Vec3::Unit(j);
    const Quat& q = s.pose.bone_local_rotation[b];
    dtheta.col(j) = (rotation_vector(quat_from_rotation_vector(Rpr.transpose() * e) * q) -
                     rotation_vector(quat_from_rotation_vector(-(Rpr.transpose() * e)) * q)) /
                    (2 * eps);
  }
  // the tangent's symmetric part loses its negative eigenvalues (torsion_step_block_local)
  const Mat3 tangent = -dtau * dtheta;
  const Eigen::SelfAdjointEigenSolver<Mat3> sym(0.5 * (tangent + tangent.transpose()));
  return tangent - sym.eigenvectors() * sym.eigenvalues().cwiseMin(0.0).asDiagonal() *
                       sym.eigenvectors().transpose();
}

// K and D of every element, assembled through the dense Jacobians
void dense_K_D(const Case& cs, MatX& K, MatX& D) {
  const Scene& sc = cs.scene;
  const SimState& s = cs.s;
  const Rig& rig = sc.rig;
  const double eps = 1e-6, h = sc.params.dt;
  K = dense_control_K(sc, s, eps);
  D.setZero(K.rows(), K.cols());
  MatX Jw, Jv, Jwp, Jvp;
  for (int b = 0; b < rig.nbone; ++b) {
    for (const Vec3* p : {&s.frames.head_world[b], &s.frames.tail_world[b]}) {
      const MatX Jp = dense::point_jacobian(rig, s, b, *p);
      D += sc.params.damping * Jp.transpose() * Jp;
    }
    dense::jacobians(rig, s, b, Jw, Jv);
    D += Jw.transpose() *
         ((1.0 - sc.params.angular_velocity_factor) / h * dense::inertia(rig, s, b)) * Jw;
    if (b == 0) continue;
    dense::jacobians(rig, s, rig.bone_parent[b], Jwp, Jvp);
    const MatX Jrel = Jw - Jwp;
    K += Jrel.transpose() * dense_torsion_block(sc, s, b, eps) * Jrel;
  }
}

TEST(ImplicitStep, AugmentedInertiaRecursionEqualsADenseSolve) {
  std::mt19937 rng(21);
  int engaged_total = 0, capped_beyond = 0;
  for (int trial = 0; trial < 40; ++trial) {
    const double h = std::pow(10.0, -2.0 + 3.0 * (trial % 7) / 6.0);  // 0.01 .. 10 s
    const double c = trial % 3 == 0 ? 0.0 : 0.5 + trial;
    const double f = trial % 4 == 0 ? 1.0 : 0.5;
    Case cs = random_case(rng, 1 + trial % 9, h, c, f);
    const Rig& rig = cs.scene.rig;
    SimState& s = cs.s;
    apply_forces(cs.scene, s);
    for (std::size_t k = 0; k < cs.scene.control_points.size(); ++k) {
      const ControlPoint& cp = cs.scene.control_points[k];
      if (*cp.spring == SpringLaw::kCapped &&
          (cp.target_world - point_on_bone(s.frames, cp.bone, cp.alpha)).norm() > *cp.cap) {
        ++capped_beyond;
      }
    }
    // tau - C from the explicit exact solve at the same forces: M qacc_explicit
    SimState explicit_state = s;
    solve_articulated(rig, cs.scene.params, explicit_state);
    const MatX M = dense::mass_matrix(rig, s);
    const VecX tau_minus_C = M * dense::aba_qacc(rig, explicit_state.joint_space.articulated);
    MatX K, D;
    dense_K_D(cs, K, D);
    const VecX v = dense::qvel(rig, s);
    const VecX expected = (M + h * D + h * h * K).partialPivLu().solve(tau_minus_C - h * K * v);

    solve_implicit(cs.scene, s);
    for (int i = 1; i < rig.nbone; ++i)
      engaged_total += s.implicit.torsion_stiffness[i].count() > 0;
    const VecX got = dense::aba_qacc(rig, s.joint_space.articulated);
    EXPECT_LT((got - expected).norm(), 1e-8 * (1.0 + expected.norm()))
        << "trial " << trial << " n " << rig.nbone << " h " << h << " c " << c << " f " << f
        << "\n got      " << got.transpose() << "\n expected " << expected.transpose();
  }
  // the cases exercised the joint blocks and the capped tangent beyond the cap
  EXPECT_GT(engaged_total, 10);
  EXPECT_GT(capped_beyond, 5);
}

// Every pivot of the recursion keeps a positive definite symmetric part at every step length.
// Pinhead with the paper's torque, posed at random (rotation vectors up to 1.5 rad per axis), at h
// from 1 ms to 4.8e3 s (by factors of 3): the torsion blocks' symmetric parts are positive
// semi-definite, so the symmetric part of M + h D + h^2 K is positive definite and so is every
// Schur complement the recursion forms (its D_i and the root's 6x6). With the tangents unclipped, a
// pivot's determinant turned negative in 27 of 1000 such poses from h ~ 1 s, and the whole matrix
// went singular in 4 (a review's scratch program, implicit_step.h); the clip is exercised here
// (more than 10 tangents with an indefinite symmetric part). Every joint a ball, its locks held by
// springs (test::with_spring_locks), since the poses turn every axis.
TEST(ImplicitStep, EveryPivotKeepsAPositiveDefiniteSymmetricPart) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Scene sc;
  sc.file = "<pinhead>";
  sc.rig = test::with_spring_locks(load_rig(test::model_path("rigs/pinhead.json")));
  sc.params = preset_params("original");
  sc.params.scheme = Scheme::kImplicit;
  sc.initial_pose = rest_pose(sc.rig);
  const Rig& rig = sc.rig;
  const auto min_sym_eigenvalue = [](const auto& m) {
    using M = std::decay_t<decltype(m)>;
    return Eigen::SelfAdjointEigenSolver<M>(0.5 * (m + m.transpose())).eigenvalues().minCoeff();
  };
  int clipped = 0, checked = 0;
  for (int trial = 0; trial < 300; ++trial) {
    SimState s0;
    size_state(sc, s0);
    s0.pose = rest_pose(rig);
    forward_kinematics(rig, s0.pose, s0.frames);
    init_joint_space(rig, s0);
    for (int i = 1; i < rig.nbone; ++i) {
      s0.pose.bone_local_rotation[i] =
          quat_from_rotation_vector(1.5 * Vec3(u(rng), u(rng), u(rng)));
    }
    world_from_joint_space(rig, s0);
    element_tangents(sc, s0);
    for (int i = 1; i < rig.nbone; ++i) {
      if (s0.implicit.torsion_stiffness[i].isZero(0.0)) continue;
      const Mat3& K = s0.implicit.torsion_block_world[i];
      ASSERT_GE(min_sym_eigenvalue(K), -1e-12 * K.norm()) << "trial " << trial << " bone " << i;
      const Vec3 theta = rotation_vector(s0.pose.bone_local_rotation[i]);
      const Mat3 tangent = s0.implicit.torsion_stiffness[i].asDiagonal() *
                           left_jacobian_inverse_transpose(theta).transpose();
      clipped += min_sym_eigenvalue(tangent) < -1e-9 * tangent.norm();
    }
    for (double h = 1e-3; h < 1e4; h *= 3.0) {
      SimState s = s0;
      apply_forces(sc, s);
      solve_implicit(sc, s, h);
      const ArticulatedBodyData& d = s.joint_space.articulated;
      for (int i = 1; i < rig.nbone; ++i) {
        const Mat3 D = d.D_inv[i].inverse();
        ASSERT_GT(min_sym_eigenvalue(D), 0.0) << "trial " << trial << " h " << h << " bone " << i;
      }
      Mat6 root;
      root << d.inertia_art[0].A, d.inertia_art[0].B, d.inertia_lower[0], d.inertia_art[0].C;
      ASSERT_GT(min_sym_eigenvalue(root), 0.0) << "trial " << trial << " h " << h;
      for (const Vec3& a : d.joint_accel_local) ASSERT_TRUE(a.allFinite());
      ++checked;
    }
  }
  std::cout << "pinhead at random: " << clipped
            << " torsion tangents with an indefinite symmetric part, " << checked
            << " steps checked\n";
  EXPECT_GT(clipped, 10);
}

TEST(ImplicitStep, DefaultRunsStayTheExplicitScheme) {
  // the default integration is the paper's; implicit is opt-in and implies the exact solve
  EXPECT_EQ(preset_params("original").scheme, Scheme::kGaussSeidel);
  EXPECT_EQ(preset_params("paper").scheme, Scheme::kGaussSeidel);
  EngineParams p = preset_params("original");
  EXPECT_FALSE(p.joint_space());
  p.scheme = Scheme::kImplicit;
  EXPECT_TRUE(p.joint_space());
}

}  // namespace
}  // namespace physik
