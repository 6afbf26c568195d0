// The OPC UA server as a child process: `node <dir>/server.mjs`, its channel (channel.h) on
// fd 3, one end of a Unix stream socket pair; its stdout and stderr go to our stderr (the
// library's notices never mix with a run's summary), its stdin is /dev/null.
#pragma once

#include <string>
#include <sys/types.h>

namespace plant::opcua {

class Child {
public:
    Child() = default;
    ~Child();  // stops it (stop(5))
    Child(const Child&) = delete;
    Child& operator=(const Child&) = delete;

    // Starts `node script`; `fd` gets our end of the channel. False with `error` (no node
    // on PATH, no script).
    bool start(const std::string& node, const std::string& script, int& fd, std::string& error);
    // Waits up to `grace` s for it to exit by itself (it does once its channel ends), then
    // sends SIGTERM, then SIGKILL. Returns how it ended, in words ("" for exit status 0).
    std::string stop(double grace);
    // How it ended if it has ("" while it runs or after a clean exit), without waiting.
    std::string ended();
    pid_t pid() const { return pid_; }

private:
    pid_t pid_ = -1;
    int status_ = 0;
    bool reaped_ = false;
};

// Describes a waitpid() status: "exit status 1", "killed by signal 9"; "" for exit 0.
std::string describe_status(int status);

}  // namespace plant::opcua
