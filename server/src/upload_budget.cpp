#include "upload_budget.hpp"

#include <algorithm>
#include <sstream>

#include "http_errors.hpp"
#include "oer/core/error.hpp"
#include "oer/core/size_text.hpp"

namespace oer::server {

UploadBudget::Lease::Lease(Lease&& other) noexcept
    : budget_(std::exchange(other.budget_, nullptr)), cost_(other.cost_) {}

UploadBudget::Lease::~Lease() {
    if (budget_) {
        budget_->release(cost_);
    }
}

UploadBudget::Lease UploadBudget::acquire(std::uint64_t cost, std::uint64_t upload_bytes,
                                          const std::string& what) {
    if (limits_.expansion > 0) {
        const std::uint64_t allowed = std::max(kExpansionFloor, limits_.expansion * upload_bytes);
        if (cost > allowed) {
            throw Error(ErrorKind::LimitExceeded,
                        what + " would take " + mebibytes(cost) + " to decode and preprocess, " +
                            "more than its " + std::to_string(upload_bytes) + " bytes may (" +
                            std::to_string(limits_.expansion) + " times their size, or " +
                            mebibytes(kExpansionFloor) + ")");
        }
    }
    if (cost > limits_.bytes) {
        throw Error(ErrorKind::LimitExceeded,
                    what + " would take " + mebibytes(cost) +
                        " to decode and preprocess, more than the server's upload memory (" +
                        mebibytes(limits_.bytes) + ")");
    }
    const std::lock_guard lock(mutex_);
    if (busy_ >= limits_.slots || reserved_ + cost > limits_.bytes) {
        throw unavailable("the server is decoding as many uploads as it may at once (" +
                              std::to_string(busy_) + " of " + std::to_string(limits_.slots) +
                              ", " + mebibytes(reserved_) + " of " + mebibytes(limits_.bytes) +
                              " reserved; this one needs " + mebibytes(cost) + ")",
                          kRetryAfterSeconds);
    }
    ++busy_;
    reserved_ += cost;
    if (observer_) {
        observer_(busy_, reserved_);
    }
    return Lease(this, cost);
}

void UploadBudget::release(std::uint64_t cost) {
    const std::lock_guard lock(mutex_);
    --busy_;
    reserved_ -= cost;
    if (observer_) {
        observer_(busy_, reserved_);
    }
}

std::uint64_t UploadBudget::reserved_bytes() const {
    const std::lock_guard lock(mutex_);
    return reserved_;
}

int UploadBudget::busy_slots() const {
    const std::lock_guard lock(mutex_);
    return busy_;
}

}  // namespace oer::server
