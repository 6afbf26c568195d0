// Whole-buffer reads and writes on a file descriptor (a pipe, a socket): a reader gets what
// has arrived (a pipe's data in parts past PIPE_BUF, 4 KiB), a writer may write less than asked,
// and a signal may interrupt either call. Used by the OPC UA link's channel and by the
// benchmarks' child runs; header-only, so a target that does not link the runtime may use it.
#pragma once

#include <cerrno>
#include <cstddef>
#include <unistd.h>

namespace plant::engine {

namespace detail {
// Calls io(fd, p, n) until all n bytes went through; false on an error or the end of the input.
template <class Io, class Byte>
bool whole(Io io, int fd, Byte* p, size_t n) {
    while (n > 0) {
        const ssize_t k = io(fd, p, n);
        if (k < 0 && errno == EINTR) continue;
        if (k <= 0) return false;
        p += k;
        n -= size_t(k);
    }
    return true;
}
}  // namespace detail

inline bool write_all(int fd, const void* data, size_t n) {
    return detail::whole(::write, fd, static_cast<const char*>(data), n);
}
inline bool read_all(int fd, void* data, size_t n) { return detail::whole(::read, fd, static_cast<char*>(data), n); }

}  // namespace plant::engine
