#include "opcua/child.h"

#include <fmt/format.h>

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <thread>
#include <vector>

extern char** environ;

namespace plant::opcua {

std::string describe_status(int status) {
    if (WIFEXITED(status)) return WEXITSTATUS(status) == 0 ? "" : fmt::format("exit status {}", WEXITSTATUS(status));
    if (WIFSIGNALED(status)) return fmt::format("killed by signal {} ({})", WTERMSIG(status), strsignal(WTERMSIG(status)));
    return "ended";
}

Child::~Child() { stop(5); }

bool Child::start(const std::string& node, const std::string& script, int& fd, std::string& error) {
    if (access(script.c_str(), R_OK) != 0) {
        error = fmt::format("no OPC UA server script '{}' (PLANT_OPCUA_DIR names its folder)", script);
        return false;
    }
    int sv[2];
    if (socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, sv) != 0) {
        error = fmt::format("socketpair: {}", std::strerror(errno));
        return false;
    }
    posix_spawn_file_actions_t fa;
    posix_spawn_file_actions_init(&fa);
    posix_spawn_file_actions_addopen(&fa, 0, "/dev/null", O_RDONLY, 0);
    posix_spawn_file_actions_adddup2(&fa, 2, 1);      // its notices to our stderr
    posix_spawn_file_actions_adddup2(&fa, sv[1], 3);  // dup2 clears close-on-exec on fd 3
    std::vector<char*> argv = {const_cast<char*>(node.c_str()), const_cast<char*>(script.c_str()), nullptr};
    // A process group of its own: Ctrl-C in a terminal reaches the plant, which ends the run
    // and then the channel; the server goes when the channel does.
    posix_spawnattr_t attr;
    posix_spawnattr_init(&attr);
    posix_spawnattr_setflags(&attr, POSIX_SPAWN_SETPGROUP);
    posix_spawnattr_setpgroup(&attr, 0);
    pid_t pid = -1;
    const int rc = posix_spawnp(&pid, node.c_str(), &fa, &attr, argv.data(), environ);
    posix_spawnattr_destroy(&attr);
    posix_spawn_file_actions_destroy(&fa);
    ::close(sv[1]);
    if (rc != 0) {
        ::close(sv[0]);
        error = fmt::format("cannot start '{}': {} (the OPC UA server runs on Node.js: install it, or name it in PLANT_NODE)",
                            node, std::strerror(rc));
        return false;
    }
    pid_ = pid;
    reaped_ = false;
    fd = sv[0];
    return true;
}

std::string Child::ended() {
    if (pid_ < 0) return "";
    if (!reaped_) {
        const pid_t r = waitpid(pid_, &status_, WNOHANG);
        if (r != pid_) return "";
        reaped_ = true;
    }
    return describe_status(status_);
}

std::string Child::stop(double grace) {
    if (pid_ < 0) return "";
    using Clock = std::chrono::steady_clock;
    auto wait_for = [&](double seconds) {
        const auto until = Clock::now() + std::chrono::duration<double>(seconds);
        while (!reaped_) {
            const pid_t r = waitpid(pid_, &status_, WNOHANG);
            if (r == pid_ || (r < 0 && errno == ECHILD)) {
                reaped_ = true;
                break;
            }
            if (Clock::now() >= until) return false;
            std::this_thread::sleep_for(std::chrono::milliseconds(10));
        }
        return true;
    };
    if (!wait_for(grace)) {
        kill(pid_, SIGTERM);
        if (!wait_for(2)) {
            kill(pid_, SIGKILL);
            wait_for(10);
        }
    }
    const std::string how = reaped_ ? describe_status(status_) : "not reaped";
    pid_ = -1;
    return how;
}

}  // namespace plant::opcua
