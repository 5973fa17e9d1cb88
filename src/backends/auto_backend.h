// The "auto" backend (mvr/backends.h kAutoBackend): not a renderer of its own but a pick among
// the registry's rows, measured on the first frame of each kind of request. Internal to
// mvr_backends: callers reach it through findBackend("auto") / makeBackend("auto").
#pragma once

#include <memory>

#include "mvr/backends.h"

namespace mvr::detail {

/// The backend "auto" with `options` passed on to the backends it measures.
std::unique_ptr<Backend> makeAutoBackend(const BackendOptions& options);

}  // namespace mvr::detail
