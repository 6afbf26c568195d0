// SIGINT and SIGTERM during a run (plant run): the first asks the run to stop at the end of
// the current step, so that it can flush its trace and print its summary; a second one
// ends the process at once, with the same exit code.
#pragma once

namespace plant::engine {

// Installs the handlers for its lifetime and restores the previous ones after. One at a time.
class InterruptGuard {
public:
    InterruptGuard();
    ~InterruptGuard();
    InterruptGuard(const InterruptGuard&) = delete;
    InterruptGuard& operator=(const InterruptGuard&) = delete;

    // The signal that asked to stop (SIGINT, SIGTERM), or 0. Cheap: read every step.
    static int requested();
    // A run stopped by signal `sig` exits with 128 + sig: 130 for SIGINT, 143 for SIGTERM.
    static int exit_code(int sig) { return 128 + sig; }
    static const char* name(int sig);
};

}  // namespace plant::engine
