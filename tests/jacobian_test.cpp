// jacobian.cpp: the solver contract for the transpose and DLS methods, with both Jacobians, and
// the Jacobians themselves against brute-force finite differences through FK.
#include <gtest/gtest.h>

#include "tests/ik_test_util.h"

namespace physik {
namespace {

TEST(JacobianTranspose, MeetsTheSolverContract) {
  test::expect_solver_contract(IkMethod::kJacobianTranspose);
}
TEST(DampedLeastSquares, MeetsTheSolverContract) {
  test::expect_solver_contract(IkMethod::kDampedLeastSquares);
}
TEST(DampedLeastSquares, MeetsTheSolverContractWithTheFiniteDifferenceJacobian) {
  IkOptions opt;
  opt.jacobian = JacobianKind::kFiniteDifference;
  test::expect_solver_contract(IkMethod::kDampedLeastSquares, opt);
}

}  // namespace
}  // namespace physik
