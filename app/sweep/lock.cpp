// The --out folder belongs to one sweep at a time. DIR/.lock is locked with flock(2) while a
// sweep (or --resume) runs there: the kernel releases the lock when its process ends, however
// it ends, so a lock left by a killed sweep is simply taken over, and one held by a live
// process is refused. The file says who holds it, for the message.
#include "sweep.h"

#include <fmt/format.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <ctime>
#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

namespace plant::sweep {

namespace {

std::string read_all(int fd) {
    std::string text;
    char buf[512];
    ::lseek(fd, 0, SEEK_SET);
    for (ssize_t n; (n = ::read(fd, buf, sizeof buf)) > 0;) text.append(buf, size_t(n));
    while (!text.empty() && (text.back() == '\n' || text.back() == ' ')) text.pop_back();
    return text;
}

}  // namespace

OutLock::~OutLock() {
    if (fd_ < 0) return;
    // Removed while still locked: a sweep waiting on this file finds it gone (checked below).
    ::unlink(path_.c_str());
    ::close(fd_);
}

bool OutLock::acquire(const std::string& dir, std::string& error, std::string& note) {
    path_ = dir + "/.lock";
    for (int attempt = 0; attempt < 10; ++attempt) {
        const int fd = ::open(path_.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
        if (fd < 0) {
            error = fmt::format("cannot create {}: {}", path_, std::strerror(errno));
            return false;
        }
        if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
            const int e = errno;
            const std::string holder = read_all(fd);
            ::close(fd);
            if (e != EWOULDBLOCK) {
                error = fmt::format("cannot lock {}: {}", path_, std::strerror(e));
                return false;
            }
            error = fmt::format("{} is in use by another sweep ({}): wait for it to end, or give another --out", dir,
                                holder.empty() ? "starting" : holder);
            return false;
        }
        // The file may have been removed by the sweep that held it just before we locked it.
        struct stat by_fd {}, by_path {};
        if (::fstat(fd, &by_fd) != 0 || ::stat(path_.c_str(), &by_path) != 0 || by_fd.st_ino != by_path.st_ino ||
            by_fd.st_dev != by_path.st_dev) {
            ::close(fd);
            continue;
        }
        const std::string before = read_all(fd);
        if (!before.empty()) note = fmt::format("{} was left by a sweep that did not end ({}): taken over", path_, before);
        char host[256] = "?";
        ::gethostname(host, sizeof host - 1);
        const std::time_t now = std::time(nullptr);
        char when[32];
        std::strftime(when, sizeof when, "%Y-%m-%d %H:%M:%S", std::localtime(&now));
        const std::string me = fmt::format("pid {} on {}, since {}\n", ::getpid(), host, when);
        if (::ftruncate(fd, 0) != 0 || ::pwrite(fd, me.data(), me.size(), 0) != ssize_t(me.size())) {
            // Who holds it is only for the message; the lock itself is held.
        }
        fd_ = fd;
        return true;
    }
    error = fmt::format("cannot lock {}: it keeps being replaced", path_);
    return false;
}

}  // namespace plant::sweep
