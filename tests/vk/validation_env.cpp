// Linked into every executable that runs vk tests (this folder's and the conformance suite):
// the vk backend's validation layers on, any message a failure (vk_backend.h). Set before main,
// so every backend the tests make sees it; an explicit MVR_VK_VALIDATION wins.
#include <cstdlib>

namespace {
const int kValidationOn = (setenv("MVR_VK_VALIDATION", "1", 0), 0);
}  // namespace
