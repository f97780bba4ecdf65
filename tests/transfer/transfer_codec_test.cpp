// The stored form of a SceneTransfer (OERPRT3): what is encoded decodes to the same values,
// and damaged bytes are refused as InvalidInput, never a crash or an allocation the bytes do not
// justify.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <string>

#include "oer/core/error.hpp"
#include "oer/transfer/transfer_codec.hpp"

using namespace oer;

namespace {

// The sample's reflector slots: the ground, a material of two objects, and one object's Native
// slot (three vectors): five bounce vectors.
constexpr std::size_t kBounceVectors = 5;
constexpr std::size_t kReflectorBytes = 4 + 24 + (24 + 2 * 4) + (24 + 4);

// count points of `coefficients` values each with distinct values (and kBounceVectors bounce
// vectors when asked), so that a value read from the wrong place shows.
TransferPoints numbered_points(std::size_t count, int coefficients, bool bounce, float first) {
    TransferPoints points;
    points.count = count;
    for (std::size_t i = 0; i < count * std::size_t(coefficients); ++i) {
        points.direct.push_back(first + 0.25f * float(i));
    }
    if (bounce) {
        for (std::size_t i = 0; i < kBounceVectors * count * std::size_t(coefficients); ++i) {
            points.bounce.push_back(-first - 0.125f * float(i));
        }
    }
    return points;
}

// Two objects (two primitives, then one) and a 3 x 3 ground grid, order 2, one bounce.
SceneTransfer sample_transfer() {
    SceneTransfer transfer;
    transfer.order = 2;
    transfer.bounce = Bounce::One;
    transfer.rays = 196;
    transfer.bake_ms = 12.5;
    using Kind = ReflectorSlot::Kind;
    transfer.reflectors = {{Kind::Ground, {}, 0, glm::vec3(0.8f)},
                           {Kind::Material, {0, 1}, 2, glm::vec3(0.5f, 0.25f, 0.125f)},
                           {Kind::Native, {1}, 0, glm::vec3(0.0f)}};
    const int coefficients = transfer.coefficients();
    transfer.objects = {{numbered_points(3, coefficients, true, 1.0f),
                         numbered_points(1, coefficients, true, 100.0f)},
                        {numbered_points(2, coefficients, true, -7.0f)}};
    GroundTransfer ground;
    ground.centre = {0.5f, -2.0f};
    ground.half_size = 3.0f;
    ground.height = -0.25f;
    ground.resolution = 3;
    ground.points = numbered_points(9, coefficients, true, 1000.0f);
    transfer.ground = ground;
    return transfer;
}

void expect_same_points(const TransferPoints& a, const TransferPoints& b) {
    EXPECT_EQ(a.count, b.count);
    EXPECT_EQ(a.direct, b.direct);
    EXPECT_EQ(a.bounce, b.bounce);
}

// decode_transfer(bytes) throws oer::Error of kind InvalidInput (and nothing else: no
// std::bad_alloc, no std::length_error, no crash).
void expect_invalid(const std::string& bytes, const std::string& what) {
    try {
        decode_transfer(bytes);
        ADD_FAILURE() << what << ": decoded";
    } catch (const Error& error) {
        EXPECT_EQ(error.kind(), ErrorKind::InvalidInput) << what << ": " << error.what();
    } catch (const std::exception& error) {
        ADD_FAILURE() << what << ": threw " << error.what() << ", not oer::Error";
    }
}

void put_u32_at(std::string& bytes, std::size_t offset, std::uint32_t value) {
    for (int i = 0; i < 4; ++i) {
        bytes[offset + std::size_t(i)] = char((value >> (8 * i)) & 0xffu);
    }
}

// Byte offsets of the layout (magic, version, order, bounce, rays, bake_ms, the reflector
// slots, object count, the first object's primitive count, its first primitive's point count).
constexpr std::size_t kReflectorCountOffset = 7 + 4 * 4;
constexpr std::size_t kSecondSlotObjectsOffset = kReflectorCountOffset + 4 + 24 + 20;
constexpr std::size_t kObjectCountOffset = kReflectorCountOffset + kReflectorBytes;
constexpr std::size_t kPrimitiveCountOffset = kObjectCountOffset + 4;
constexpr std::size_t kPointCountOffset = kPrimitiveCountOffset + 4;
constexpr std::size_t kFirstValueOffset = kPointCountOffset + 8 + 4;

}  // namespace

TEST(TransferCodec, RoundTripKeepsEveryValue) {
    const SceneTransfer transfer = sample_transfer();
    const SceneTransfer decoded = decode_transfer(encode_transfer(transfer));
    EXPECT_EQ(decoded.order, transfer.order);
    EXPECT_EQ(decoded.bounce, transfer.bounce);
    EXPECT_EQ(decoded.rays, transfer.rays);
    EXPECT_EQ(decoded.bake_ms, transfer.bake_ms);
    ASSERT_EQ(decoded.reflectors.size(), 3u);
    for (std::size_t s = 0; s < 3; ++s) {
        EXPECT_EQ(decoded.reflectors[s], transfer.reflectors[s]) << "slot " << s;
    }
    ASSERT_EQ(decoded.objects.size(), 2u);
    ASSERT_EQ(decoded.objects[0].size(), 2u);
    ASSERT_EQ(decoded.objects[1].size(), 1u);
    expect_same_points(decoded.objects[0][0], transfer.objects[0][0]);
    expect_same_points(decoded.objects[0][1], transfer.objects[0][1]);
    expect_same_points(decoded.objects[1][0], transfer.objects[1][0]);
    ASSERT_TRUE(decoded.ground.has_value());
    EXPECT_EQ(decoded.ground->centre, transfer.ground->centre);
    EXPECT_EQ(decoded.ground->half_size, transfer.ground->half_size);
    EXPECT_EQ(decoded.ground->height, transfer.ground->height);
    EXPECT_EQ(decoded.ground->resolution, transfer.ground->resolution);
    expect_same_points(decoded.ground->points, transfer.ground->points);
}

TEST(TransferCodec, RoundTripWithoutBounceOrGround) {
    SceneTransfer transfer;
    transfer.order = 5;
    transfer.bounce = Bounce::None;
    transfer.rays = 64;
    transfer.objects = {{numbered_points(4, transfer.coefficients(), false, 3.0f)}};
    const SceneTransfer decoded = decode_transfer(encode_transfer(transfer));
    EXPECT_EQ(decoded.bounce, Bounce::None);
    EXPECT_FALSE(decoded.ground.has_value());
    ASSERT_EQ(decoded.objects.size(), 1u);
    ASSERT_EQ(decoded.objects[0].size(), 1u);
    expect_same_points(decoded.objects[0][0], transfer.objects[0][0]);
}

TEST(TransferCodec, EveryTruncationIsInvalidInput) {
    const std::string bytes = encode_transfer(sample_transfer());
    for (std::size_t length = 0; length < bytes.size(); ++length) {
        expect_invalid(bytes.substr(0, length), "the first " + std::to_string(length) + " of " +
                                                    std::to_string(bytes.size()) + " bytes");
    }
    expect_invalid(bytes + '\0', "one byte more");
}

TEST(TransferCodec, HugeClaimedCountsAreRefusedBeforeAllocating) {
    const std::string bytes = encode_transfer(sample_transfer());
    // 2^32 - 1 objects or primitives, or 2^63 points: allocating for them would throw
    // std::bad_alloc or std::length_error; the decoder compares them with the bytes first.
    std::string objects = bytes;
    put_u32_at(objects, kObjectCountOffset, std::numeric_limits<std::uint32_t>::max());
    expect_invalid(objects, "2^32 - 1 objects");
    std::string primitives = bytes;
    put_u32_at(primitives, kPrimitiveCountOffset, std::numeric_limits<std::uint32_t>::max());
    expect_invalid(primitives, "2^32 - 1 primitives");
    std::string points = bytes;
    put_u32_at(points, kPointCountOffset + 4, 0x80000000u);
    expect_invalid(points, "2^63 points");
    std::string slots = bytes;
    put_u32_at(slots, kReflectorCountOffset, std::numeric_limits<std::uint32_t>::max());
    expect_invalid(slots, "2^32 - 1 reflector slots");
    std::string objects_of_slot = bytes;
    put_u32_at(objects_of_slot, kSecondSlotObjectsOffset,
               std::numeric_limits<std::uint32_t>::max());
    expect_invalid(objects_of_slot, "2^32 - 1 reflecting objects");
    std::string fewer_slots = bytes;
    put_u32_at(fewer_slots, kReflectorCountOffset, 2);
    expect_invalid(fewer_slots, "two slots where the vectors are sized for three");
    std::string kind = bytes;
    put_u32_at(kind, kReflectorCountOffset + 4, 4);
    expect_invalid(kind, "a reflector kind past Unit");
}

TEST(TransferCodec, NonFiniteValuesAreRefused) {
    for (const float bad :
         {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity()}) {
        SceneTransfer transfer = sample_transfer();
        transfer.objects[1][0].direct[1] = bad;
        expect_invalid(encode_transfer(transfer), "a non-finite direct value");
        transfer = sample_transfer();
        transfer.ground->points.bounce.back() = bad;
        expect_invalid(encode_transfer(transfer), "a non-finite ground bounce value");
    }
    // The same NaN written into the bytes of an intact encoding, where the first value lies.
    std::string bytes = encode_transfer(sample_transfer());
    put_u32_at(bytes, kFirstValueOffset, 0x7fc00000u);
    expect_invalid(bytes, "a NaN at the first value");
}

TEST(TransferCodec, WrongMagicVersionAndFieldsAreRefused) {
    const std::string bytes = encode_transfer(sample_transfer());
    std::string magic = bytes;
    magic[0] = 'X';
    expect_invalid(magic, "a wrong magic");
    std::string version = bytes;
    version[6] = '2';
    expect_invalid(version, "version 2, whose slots were of another form");
    SceneTransfer no_slots = sample_transfer();
    no_slots.reflectors.clear();
    expect_invalid(encode_transfer(no_slots), "one bounce without reflector slots");
    SceneTransfer slots_without_bounce;
    slots_without_bounce.order = 2;
    slots_without_bounce.bounce = Bounce::None;
    slots_without_bounce.rays = 64;
    slots_without_bounce.reflectors = {{ReflectorSlot::Kind::Ground, {}, 0, glm::vec3(0.8f)}};
    expect_invalid(encode_transfer(slots_without_bounce), "reflector slots without a bounce");
    SceneTransfer ground_with_objects = sample_transfer();
    ground_with_objects.reflectors[0].objects = {0};
    expect_invalid(encode_transfer(ground_with_objects), "the ground's slot naming an object");
    SceneTransfer material_of_nothing = sample_transfer();
    material_of_nothing.reflectors[1].objects.clear();
    expect_invalid(encode_transfer(material_of_nothing), "a material slot of no object");
    std::string order = bytes;
    put_u32_at(order, 7, std::uint32_t(kTransferBakeOrder + 1));
    expect_invalid(order, "an order above the bake's");
}
