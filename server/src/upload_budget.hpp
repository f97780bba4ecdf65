#pragma once
// What decoding and preprocessing uploads may hold at once: a few slots (one upload each) and
// bytes of memory, reserved from a cost estimated before anything is allocated (from a map's
// header, a mesh's size). An upload that finds no free slot or not enough free bytes is
// answered 503 with Retry-After at once rather than queued, so that the server's memory is
// bounded by its budget, not by how many uploads arrive together; the client comes back later.
//
// An upload may also not expand beyond a multiple of its own size (a decompression bomb: a
// small file whose header claims a large image that its bytes really encode, such as a
// run-length .hdr of one colour): its cost must stay within max(kExpansionFloor, expansion x its
// bytes), which bounds what any one upload of N bytes can make the server hold. The default,
// 200, is what real panoramas need: a phone's 8192x4096 JPEG of 10 MB takes about 97 times its
// size to decode (571 MB: the float map, the 8-bit rows, OpenImageIO's conversion buffer) and
// preprocess, a 5376x2688 one of 6 MB about 70 times; an expansion of 40 would refuse both. Natural
// HDR maps (EXR, RLE .hdr) take 6 to 12 times theirs.
#include <cstdint>
#include <functional>
#include <mutex>
#include <string>

namespace oer::server {

// Below this cost every upload may expand as it likes: a small map or mesh is never a bomb.
inline constexpr std::uint64_t kExpansionFloor = 64ull << 20;

struct UploadBudgetLimits {
    std::uint64_t bytes = 2ull << 30;  // memory all uploads being decoded may hold together
    int slots = 2;                     // uploads decoded at once
    std::uint64_t expansion = 200;     // cost at most this many times the upload's bytes; 0: any
};

class UploadBudget {
  public:
    // Called with the busy slots and reserved bytes whenever they change (for gauges).
    using Observer = std::function<void(int busy_slots, std::uint64_t reserved_bytes)>;

    explicit UploadBudget(const UploadBudgetLimits& limits, Observer observer = {})
        : limits_(limits), observer_(std::move(observer)) {}

    // A reservation, given back when it is destroyed.
    class Lease {
      public:
        Lease(Lease&& other) noexcept;
        Lease& operator=(Lease&&) = delete;
        Lease(const Lease&) = delete;
        ~Lease();

      private:
        friend class UploadBudget;
        Lease(UploadBudget* budget, std::uint64_t cost) : budget_(budget), cost_(cost) {}
        UploadBudget* budget_;
        std::uint64_t cost_;
    };

    // Reserves a slot and `cost` bytes for an upload of `upload_bytes` bytes, `what` naming it
    // in messages ("a 8192x4096 map"). Throws oer::Error (LimitExceeded: 413) when the cost is
    // over what the upload may expand to or over the whole budget (it could never run), and
    // HttpError 503 with Retry-After when the slots or the bytes are taken now.
    Lease acquire(std::uint64_t cost, std::uint64_t upload_bytes, const std::string& what);

    std::uint64_t reserved_bytes() const;
    int busy_slots() const;

  private:
    void release(std::uint64_t cost);

    const UploadBudgetLimits limits_;
    const Observer observer_;
    mutable std::mutex mutex_;
    std::uint64_t reserved_ = 0;
    int busy_ = 0;
};

}  // namespace oer::server
