// Whole-buffer reads and writes on a file descriptor (a pipe from a benchmark's child run):
// a pipe hands a reader what has arrived, in parts past PIPE_BUF (4 KiB), and a signal may
// interrupt either call.
#pragma once

#include <cerrno>
#include <cstddef>
#include <unistd.h>

namespace plant::bench {

inline bool write_all(int fd, const void* data, size_t n) {
    const char* p = static_cast<const char*>(data);
    while (n > 0) {
        const ssize_t w = ::write(fd, p, n);
        if (w < 0 && errno == EINTR) continue;
        if (w <= 0) return false;
        p += w;
        n -= static_cast<size_t>(w);
    }
    return true;
}

inline bool read_all(int fd, void* data, size_t n) {
    char* p = static_cast<char*>(data);
    while (n > 0) {
        const ssize_t r = ::read(fd, p, n);
        if (r < 0 && errno == EINTR) continue;
        if (r <= 0) return false;
        p += r;
        n -= static_cast<size_t>(r);
    }
    return true;
}

}  // namespace plant::bench
