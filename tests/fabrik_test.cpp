// fabrik.cpp: the solver contract (ik_test_util.h) and what is particular to this solver.
#include <gtest/gtest.h>

#include "tests/ik_test_util.h"

namespace physik {
namespace {

TEST(Fabrik, MeetsTheSolverContract) { test::expect_solver_contract(IkMethod::kFabrik); }

}  // namespace
}  // namespace physik
