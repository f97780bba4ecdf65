// The stored form of a SceneTransfer (oer/scene/scene_transfer.hpp). Every count is checked against
// the bytes that remain before anything is allocated, so a damaged or hostile entry costs no more
// memory than its own size.
#include <bit>
#include <cmath>
#include <string>

#include "oer/core/error.hpp"
#include "oer/transfer/transfer_codec.hpp"

namespace oer {
namespace {

constexpr char kMagic[] = "OERPRT";
constexpr char kVersion = '3';
constexpr std::size_t kMagicBytes = 6;
constexpr int kMaxRays = 1 << 20;
constexpr int kMaxGroundResolution = 4096;

[[noreturn]] void invalid_transfer(const std::string& message) {
    throw Error(ErrorKind::InvalidInput, "stored transfer: " + message);
}

void put_u32(std::string& out, std::uint32_t value) {
    for (int shift = 0; shift < 32; shift += 8) {
        out.push_back(char((value >> shift) & 0xffu));
    }
}

void put_u64(std::string& out, std::uint64_t value) {
    put_u32(out, std::uint32_t(value & 0xffffffffu));
    put_u32(out, std::uint32_t(value >> 32));
}

void put_f32(std::string& out, float value) {
    put_u32(out, std::bit_cast<std::uint32_t>(value));
}

void put_floats(std::string& out, const std::vector<float>& values) {
    for (const float value : values) {
        put_f32(out, value);
    }
}

class Reader {
  public:
    explicit Reader(std::string_view bytes) : bytes_(bytes) {}

    std::uint32_t u32(const char* what) {
        need(4, what);
        std::uint32_t value = 0;
        for (int i = 0; i < 4; ++i) {
            value |= std::uint32_t(std::uint8_t(bytes_[offset_ + std::size_t(i)])) << (8 * i);
        }
        offset_ += 4;
        return value;
    }
    std::uint64_t u64(const char* what) {
        const std::uint64_t low = u32(what);
        return low | (std::uint64_t(u32(what)) << 32);
    }
    float f32(const char* what) {
        const float value = std::bit_cast<float>(u32(what));
        if (!std::isfinite(value)) {
            invalid_transfer(std::string(what) + " holds a non-finite value at byte " +
                             std::to_string(offset_ - 4));
        }
        return value;
    }
    // count floats, after checking that the bytes hold them.
    std::vector<float> floats(std::uint64_t count, const char* what) {
        if (count > remaining() / 4) {
            invalid_transfer(std::string(what) + ": " + std::to_string(count) + " values need " +
                             std::to_string(count * 4) + " bytes, " + std::to_string(remaining()) +
                             " remain (truncated or damaged)");
        }
        std::vector<float> values(count);
        for (float& value : values) {
            value = f32(what);
        }
        return values;
    }
    std::size_t remaining() const { return bytes_.size() - offset_; }

  private:
    void need(std::size_t count, const char* what) {
        if (remaining() < count) {
            invalid_transfer(std::string("truncated: ") + what + " needs " + std::to_string(count) +
                             " bytes at byte " + std::to_string(offset_) + ", " +
                             std::to_string(remaining()) + " remain");
        }
    }
    std::string_view bytes_;
    std::size_t offset_ = 0;
};

void put_reflectors(std::string& out, const std::vector<ReflectorSlot>& reflectors) {
    put_u32(out, std::uint32_t(reflectors.size()));
    for (const ReflectorSlot& slot : reflectors) {
        put_u32(out, std::uint32_t(slot.kind));
        put_u32(out, slot.material);
        put_f32(out, slot.albedo.r);
        put_f32(out, slot.albedo.g);
        put_f32(out, slot.albedo.b);
        put_u32(out, std::uint32_t(slot.objects.size()));
        for (const std::uint32_t object : slot.objects) {
            put_u32(out, object);
        }
    }
}

// Each slot takes at least 24 bytes and each of its objects 4: their counts are bounded by the
// bytes before anything is sized. Whether the objects and materials exist is the frame's to
// check (transfer_misfit), which knows the meshes.
std::vector<ReflectorSlot> read_reflectors(Reader& in, Bounce bounce) {
    const std::uint32_t count = in.u32("reflector count");
    if ((count == 0) != (bounce == Bounce::None)) {
        invalid_transfer(std::to_string(count) + " reflector slots for bounce " +
                         (bounce == Bounce::One ? "one" : "none"));
    }
    if (count > in.remaining() / 24) {
        invalid_transfer(std::to_string(count) + " reflector slots cannot fit the " +
                         std::to_string(in.remaining()) + " bytes left");
    }
    std::vector<ReflectorSlot> reflectors(count);
    for (ReflectorSlot& slot : reflectors) {
        const std::uint32_t kind = in.u32("reflector kind");
        if (kind > std::uint32_t(ReflectorSlot::Kind::Unit)) {
            invalid_transfer("reflector kind " + std::to_string(kind) + " is not one of 0 to 3");
        }
        slot.kind = ReflectorSlot::Kind(kind);
        slot.material = in.u32("reflector material");
        for (int c = 0; c < 3; ++c) {
            slot.albedo[c] = in.f32("reflector albedo");
        }
        const std::uint32_t objects = in.u32("reflector object count");
        if (objects > in.remaining() / 4) {
            invalid_transfer(std::to_string(objects) + " reflecting objects cannot fit the " +
                             std::to_string(in.remaining()) + " bytes left");
        }
        if ((slot.kind == ReflectorSlot::Kind::Ground) != (objects == 0)) {
            invalid_transfer(slot.kind == ReflectorSlot::Kind::Ground
                                 ? "the ground's reflector slot names objects"
                                 : "a reflector slot of objects names none");
        }
        slot.objects.resize(objects);
        for (std::uint32_t& object : slot.objects) {
            object = in.u32("reflecting object");
        }
    }
    return reflectors;
}

void put_points(std::string& out, const TransferPoints& points) {
    put_u64(out, points.count);
    put_u32(out, points.bounce.empty() ? 0u : 1u);
    put_floats(out, points.direct);
    put_floats(out, points.bounce);
}

TransferPoints read_points(Reader& in, int coefficients, Bounce bounce, std::size_t vectors,
                           const char* what) {
    TransferPoints points;
    points.count = std::size_t(in.u64(what));
    const std::uint32_t has_bounce = in.u32(what);
    if (has_bounce != (bounce == Bounce::One ? 1u : 0u)) {
        invalid_transfer(std::string(what) + (has_bounce ? " has" : " lacks") +
                         " bounce vectors, but the transfer's bounce is " +
                         (bounce == Bounce::One ? "one" : "none"));
    }
    // Each point takes at least coefficients * 4 bytes: a count the bytes cannot hold is refused
    // before its vector is sized.
    if (points.count > in.remaining() / (std::size_t(coefficients) * 4)) {
        invalid_transfer(std::string(what) + ": " + std::to_string(points.count) +
                         " points cannot fit the " + std::to_string(in.remaining()) +
                         " bytes left");
    }
    points.direct = in.floats(std::uint64_t(points.count) * std::uint64_t(coefficients), what);
    if (has_bounce) {
        points.bounce =
            in.floats(std::uint64_t(points.count) * vectors * std::uint64_t(coefficients), what);
    }
    return points;
}

}  // namespace

std::string encode_transfer(const SceneTransfer& transfer) {
    std::string out(kMagic, kMagicBytes);
    out.push_back(kVersion);
    put_u32(out, std::uint32_t(transfer.order));
    put_u32(out, transfer.bounce == Bounce::One ? 1u : 0u);
    put_u32(out, std::uint32_t(transfer.rays));
    put_f32(out, float(transfer.bake_ms));
    put_reflectors(out, transfer.reflectors);
    put_u32(out, std::uint32_t(transfer.objects.size()));
    for (const std::vector<TransferPoints>& object : transfer.objects) {
        put_u32(out, std::uint32_t(object.size()));
        for (const TransferPoints& points : object) {
            put_points(out, points);
        }
    }
    put_u32(out, transfer.ground ? 1u : 0u);
    if (transfer.ground) {
        const GroundTransfer& ground = *transfer.ground;
        put_f32(out, ground.centre.x);
        put_f32(out, ground.centre.y);
        put_f32(out, ground.half_size);
        put_f32(out, ground.height);
        put_u32(out, std::uint32_t(ground.resolution));
        put_points(out, ground.points);
    }
    return out;
}

SceneTransfer decode_transfer(std::string_view bytes) {
    if (bytes.size() < kMagicBytes + 1 || bytes.substr(0, kMagicBytes) != kMagic) {
        invalid_transfer("wrong magic: the bytes do not start with \"OERPRT\"");
    }
    if (bytes[kMagicBytes] != kVersion) {
        invalid_transfer("version '" + std::string(1, bytes[kMagicBytes]) +
                         "' is not the supported '" + std::string(1, kVersion) + "'");
    }
    Reader in(bytes.substr(kMagicBytes + 1));
    SceneTransfer transfer;
    const std::uint32_t order = in.u32("order");
    if (order < 1 || order > std::uint32_t(kTransferBakeOrder)) {
        invalid_transfer("order " + std::to_string(order) + " is not in [1, " +
                         std::to_string(kTransferBakeOrder) + "]");
    }
    transfer.order = int(order);
    const std::uint32_t bounce = in.u32("bounce");
    if (bounce > 1) {
        invalid_transfer("bounce " + std::to_string(bounce) + " is neither 0 (none) nor 1 (one)");
    }
    transfer.bounce = bounce == 1 ? Bounce::One : Bounce::None;
    const std::uint32_t rays = in.u32("rays");
    if (rays < 1 || rays > std::uint32_t(kMaxRays)) {
        invalid_transfer("rays " + std::to_string(rays) + " is not in [1, " +
                         std::to_string(kMaxRays) + "]");
    }
    transfer.rays = int(rays);
    transfer.bake_ms = in.f32("bake_ms");
    transfer.reflectors = read_reflectors(in, transfer.bounce);
    const std::size_t vectors = bounce_vectors(transfer.reflectors);
    const int coefficients = transfer.coefficients();
    // Every object and primitive takes at least 4 and 12 bytes: their counts are bounded by the
    // bytes before the vectors of them are sized.
    const std::uint32_t objects = in.u32("object count");
    if (objects > in.remaining() / 4) {
        invalid_transfer(std::to_string(objects) + " objects cannot fit the " +
                         std::to_string(in.remaining()) + " bytes left");
    }
    transfer.objects.resize(objects);
    for (std::vector<TransferPoints>& object : transfer.objects) {
        const std::uint32_t primitives = in.u32("primitive count");
        if (primitives > in.remaining() / 12) {
            invalid_transfer(std::to_string(primitives) + " primitives cannot fit the " +
                             std::to_string(in.remaining()) + " bytes left");
        }
        object.reserve(primitives);
        for (std::uint32_t p = 0; p < primitives; ++p) {
            object.push_back(
                read_points(in, coefficients, transfer.bounce, vectors, "an object's points"));
        }
    }
    const std::uint32_t has_ground = in.u32("ground flag");
    if (has_ground > 1) {
        invalid_transfer("ground flag " + std::to_string(has_ground) + " is neither 0 nor 1");
    }
    if (has_ground) {
        GroundTransfer ground;
        ground.centre.x = in.f32("ground centre");
        ground.centre.y = in.f32("ground centre");
        ground.half_size = in.f32("ground half size");
        ground.height = in.f32("ground height");
        if (!(ground.half_size > 0.0f)) {
            invalid_transfer("ground half size " + std::to_string(ground.half_size) +
                             " is not positive");
        }
        const std::uint32_t resolution = in.u32("ground resolution");
        if (resolution < 1 || resolution > std::uint32_t(kMaxGroundResolution)) {
            invalid_transfer("ground resolution " + std::to_string(resolution) + " is not in [1, " +
                             std::to_string(kMaxGroundResolution) + "]");
        }
        ground.resolution = int(resolution);
        ground.points =
            read_points(in, coefficients, transfer.bounce, vectors, "the ground's points");
        if (ground.points.count != std::size_t(resolution) * resolution) {
            invalid_transfer("the ground has " + std::to_string(ground.points.count) +
                             " points, not resolution^2 = " +
                             std::to_string(std::size_t(resolution) * resolution));
        }
        transfer.ground = std::move(ground);
    }
    if (in.remaining() != 0) {
        invalid_transfer(std::to_string(in.remaining()) +
                         " bytes follow the transfer's last field");
    }
    return transfer;
}

}  // namespace oer
