#pragma once
// Internal to the lighting library: a range of work cut at a fixed point over two threads, the
// projection's rows (sh_projection.cpp) and the prefilter's faces and texel rows
// (specular_environment.cpp). The cut depends on the caller's sizes alone, so that results are
// deterministic; an exception on either thread reaches the caller once both have finished.
#include <exception>
#include <thread>

namespace oer::detail {

// work(middle, count) on a second thread, work(0, middle) on this one.
template <typename Work>
void split_on_two_threads(int count, int middle, const Work& work) {
    std::exception_ptr failure;
    std::thread worker([&] {
        try {
            work(middle, count);
        } catch (...) {
            failure = std::current_exception();
        }
    });
    try {
        work(0, middle);
    } catch (...) {
        worker.join();
        throw;
    }
    worker.join();
    if (failure) {
        std::rethrow_exception(failure);
    }
}

}  // namespace oer::detail
