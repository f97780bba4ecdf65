#include "request_state.hpp"

namespace oer::server {

RequestState& current_request() {
    thread_local RequestState state;
    return state;
}

}  // namespace oer::server
