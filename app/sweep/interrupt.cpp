// Ctrl-C (SIGINT) or a batch system's SIGTERM during a sweep: the first is noted and the
// driver stops its runs, keeps every finished row and says how to complete the sweep; a
// second one ends the process at once (its runs die with it: PR_SET_PDEATHSIG, pool.cpp).
#include "sweep.h"

#include <csignal>
#include <unistd.h>

namespace plant::sweep {

namespace {

volatile std::sig_atomic_t g_signal = 0;
struct sigaction g_old_int, g_old_term;

extern "C" void on_sweep_signal(int sig) {
    if (g_signal) ::_exit(128 + sig);
    g_signal = sig;
}

}  // namespace

InterruptWatch::InterruptWatch() {
    g_signal = 0;
    struct sigaction sa {};
    sa.sa_handler = on_sweep_signal;
    sa.sa_flags = SA_RESTART;
    sigemptyset(&sa.sa_mask);
    sigaction(SIGINT, &sa, &g_old_int);
    sigaction(SIGTERM, &sa, &g_old_term);
}

InterruptWatch::~InterruptWatch() {
    sigaction(SIGINT, &g_old_int, nullptr);
    sigaction(SIGTERM, &g_old_term, nullptr);
}

int InterruptWatch::interrupted() { return g_signal; }

}  // namespace plant::sweep
