#include "engine/interrupt.h"

#include <csignal>
#include <unistd.h>

namespace plant::engine {

namespace {

volatile std::sig_atomic_t g_requested = 0;
struct sigaction g_old_int, g_old_term;

extern "C" void on_signal(int sig) {
    if (g_requested) _exit(InterruptGuard::exit_code(sig));  // the second: no waiting for a step
    g_requested = sig;
}

}  // namespace

InterruptGuard::InterruptGuard() {
    g_requested = 0;
    struct sigaction sa {};
    sa.sa_handler = on_signal;
    sa.sa_flags = SA_RESTART;  // a write to a pipe in progress goes on, rather than failing
    sigemptyset(&sa.sa_mask);
    sigaction(SIGINT, &sa, &g_old_int);
    sigaction(SIGTERM, &sa, &g_old_term);
}

InterruptGuard::~InterruptGuard() {
    sigaction(SIGINT, &g_old_int, nullptr);
    sigaction(SIGTERM, &g_old_term, nullptr);
    g_requested = 0;
}

int InterruptGuard::requested() { return g_requested; }

const char* InterruptGuard::name(int sig) { return sig == SIGTERM ? "SIGTERM" : "SIGINT"; }

}  // namespace plant::engine
