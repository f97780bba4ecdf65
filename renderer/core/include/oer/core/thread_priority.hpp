#pragma once
// Lowering one thread's priority: a server runs its throughput work (frames, bakes) below its
// request threads, which then preempt it at once.
#include <sys/resource.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <string>

#include "oer/core/error.hpp"

namespace oer {

// Adds nice (0..19) to the calling thread's nice value (Linux: setpriority on a thread id
// affects that thread alone; the threads it starts afterwards inherit it). Throws oer::Error
// (Internal) naming `whose` when the system refuses.
inline void lower_thread_priority(int nice, const std::string& whose) {
    const pid_t self = ::gettid();
    errno = 0;
    const int current = ::getpriority(PRIO_PROCESS, id_t(self));
    if ((current == -1 && errno != 0) ||
        ::setpriority(PRIO_PROCESS, id_t(self), current + nice) != 0) {
        throw Error(ErrorKind::Internal, "cannot lower " + whose + "'s priority by " +
                                             std::to_string(nice) + ": " + std::strerror(errno));
    }
}

}  // namespace oer
