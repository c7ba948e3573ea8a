#include "reference/mujoco_log.h"

#include <cstdio>

#include <mujoco/mujoco.h>

namespace physik {

namespace {
void warn_to_stderr(const char* msg) {
  std::fprintf(stderr, "mujoco warning: %s\n", msg);
}
}  // namespace

void route_mujoco_warnings_to_stderr() {
  mju_user_warning = warn_to_stderr;
}

}  // namespace physik
