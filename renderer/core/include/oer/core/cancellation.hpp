#pragma once
// Cooperative cancellation of long work (a frame's passes, a transfer bake): the caller holds a
// std::stop_source and hands its token down; the work checks it between steps short enough that
// it stops within a fraction of a second (between passes, between lights' shadow maps, between
// chunks of receivers in a bake), and leaves by throwing, so that everything it allocated is
// freed on the way out. A default-constructed token never stops.
#include <stop_token>
#include <string>
#include <string_view>

#include "oer/core/error.hpp"

namespace oer {

// Throws oer::Error (Cancelled) naming the work when a stop was requested.
inline void throw_if_stopped(const std::stop_token& stop, std::string_view work) {
    if (stop.stop_requested()) {
        throw Error(ErrorKind::Cancelled,
                    std::string(work) + " stopped: its deadline passed or nobody waits for it");
    }
}

}  // namespace oer
