#pragma once
// lavapipe backend internals that tests may look at (the backend itself: make_lavapipe_backend, backend.h).

namespace aovar::render {

// Validation-layer errors reported in this process so far (BackendOptions::validation), teardown included:
// destructors cannot throw, so a test reads this counter before and after a run to assert a clean one.
int lavapipe_validation_error_count();

}  // namespace aovar::render
