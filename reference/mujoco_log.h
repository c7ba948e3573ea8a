// MuJoCo's warnings go to stderr, prefixed, instead of MuJoCo's default MUJOCO_LOG.TXT in the
// current folder (which would litter the repository during `make reproduce`).
#pragma once

namespace physik {

// Install the handler (idempotent; call before loading a model).
void route_mujoco_warnings_to_stderr();

}  // namespace physik
