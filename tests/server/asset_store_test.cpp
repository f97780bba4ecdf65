// The asset store: content ids, round trips, restarts, atomic writes (no partial entries, no
// confusion from leftover temporary files, which a later start removes once abandoned while
// sparing writes in progress of another process sharing the folder), corruption detected and
// dropped, ids and extensions validated before any path is built, and concurrent use.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "error_kind.hpp"
#include "oer/api/content_id.hpp"
#include "oer/core/error.hpp"
#include "oer/server/asset_store.hpp"

using namespace oer;
using namespace oer::server;
using oer::testing::kind_of_failure;
namespace fs = std::filesystem;

namespace {

// SHA-256 of "abc" (FIPS 180-2, appendix B.1).
const std::string kAbcId = "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad";
const std::string kRigId(64, 'e');

std::string read_bytes(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

void write_bytes(const fs::path& path, const std::string& bytes) {
    std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
}

// Sets the file's modification time so long before now.
void set_untouched_for(const fs::path& path, std::chrono::minutes age) {
    fs::last_write_time(path, fs::file_time_type::clock::now() - age);
}

std::vector<std::string> file_names(const fs::path& folder) {
    std::vector<std::string> names;
    for (const auto& entry : fs::directory_iterator(folder)) {
        names.push_back(entry.path().filename().string());
    }
    std::sort(names.begin(), names.end());
    return names;
}

class AssetStoreTest : public ::testing::Test {
  protected:
    AssetStoreTest()
        : folder_(fs::temp_directory_path() /
                  ("oer-asset-store-test-" + std::to_string(::getpid()) + "-" +
                   ::testing::UnitTest::GetInstance()->current_test_info()->name()) /
                  "data") {}
    ~AssetStoreTest() override { fs::remove_all(folder_.parent_path()); }

    AssetStore open() {
        return AssetStore(folder_, [this](std::string_view line) {
            const std::lock_guard lock(log_mutex_);
            log_.emplace_back(line);
        });
    }

    std::vector<std::string> log() {
        const std::lock_guard lock(log_mutex_);
        return log_;
    }

    const fs::path folder_;

  private:
    std::mutex log_mutex_;
    std::vector<std::string> log_;
};

}  // namespace

TEST_F(AssetStoreTest, CreatesTheFolderAndOneSubFolderPerKind) {
    ASSERT_FALSE(fs::exists(folder_));
    const AssetStore store = open();
    EXPECT_EQ(file_names(folder_),
              (std::vector<std::string>{"environments", "mesh-summaries", "meshes", "rig-sources",
                                        "rigs", "specular", "transfer", "transfer-meshes"}));
    EXPECT_EQ(store.folder(), folder_);
}

TEST_F(AssetStoreTest, SourceIdIsTheSha256OfItsBytesAndTheFileKeepsItsExtension) {
    AssetStore store = open();
    EXPECT_EQ(store.put_source(SourceKind::Mesh, "abc", "glb"), kAbcId);
    EXPECT_EQ(read_bytes(folder_ / "meshes" / (kAbcId + ".glb")), "abc");
    const auto stored = store.get_source(SourceKind::Mesh, kAbcId);
    ASSERT_TRUE(stored.has_value());
    EXPECT_EQ(stored->bytes, "abc");
    EXPECT_EQ(stored->extension, "glb");
    EXPECT_TRUE(store.contains(SourceKind::Mesh, kAbcId));
    EXPECT_FALSE(store.contains(SourceKind::Environment, kAbcId));
    EXPECT_FALSE(store.get_source(SourceKind::Environment, kAbcId).has_value());
    EXPECT_TRUE(log().empty());
}

TEST_F(AssetStoreTest, PuttingTheSameBytesAgainKeepsOneEntry) {
    AssetStore store = open();
    EXPECT_EQ(store.put_source(SourceKind::Environment, "abc", "exr"), kAbcId);
    EXPECT_EQ(store.put_source(SourceKind::Environment, "abc", "exr"), kAbcId);
    EXPECT_EQ(file_names(folder_ / "environments"), std::vector<std::string>{kAbcId + ".exr"});
}

TEST_F(AssetStoreTest, SameBytesUnderAnotherExtensionAreRejected) {
    AssetStore store = open();
    store.put_source(SourceKind::Mesh, "abc", "obj");
    EXPECT_EQ(kind_of_failure([&] { store.put_source(SourceKind::Mesh, "abc", "gltf"); }),
              ErrorKind::InvalidInput);
    EXPECT_EQ(file_names(folder_ / "meshes"), std::vector<std::string>{kAbcId + ".obj"});
    EXPECT_EQ(store.get_source(SourceKind::Mesh, kAbcId)->extension, "obj");
}

TEST_F(AssetStoreTest, DerivedEntryRoundTripsInsideASealedFile) {
    AssetStore store = open();
    const std::string rig = R"({"id":"x","lights":[]})";
    store.put_derived(DerivedKind::Rig, kRigId, rig);
    EXPECT_EQ(store.get_derived(DerivedKind::Rig, kRigId), rig);
    EXPECT_TRUE(store.contains(DerivedKind::Rig, kRigId));
    EXPECT_EQ(read_bytes(folder_ / "rigs" / (kRigId + ".sealed")),
              "oer-sealed-v1 " + api::sha256_hex(rig) + " 22\n" + rig);
}

// A rig's specular cube is binary (half floats, zero bytes included) and lives under its rig's
// id in a folder of its own, apart from the rig.
TEST_F(AssetStoreTest, SpecularEntryIsKeptByRigIdBesideTheRig) {
    AssetStore store = open();
    const std::string cube = std::string("OERSPEC1\0\x01\0\0", 12) + std::string(1, '\xff');
    store.put_derived(DerivedKind::Rig, kRigId, "rig");
    store.put_derived(DerivedKind::Specular, kRigId, cube);
    EXPECT_EQ(store.get_derived(DerivedKind::Specular, kRigId), cube);
    EXPECT_EQ(store.get_derived(DerivedKind::Rig, kRigId), "rig");
    EXPECT_EQ(file_names(folder_ / "specular"), std::vector<std::string>{kRigId + ".sealed"});
    EXPECT_TRUE(store.remove(DerivedKind::Specular, kRigId));
    EXPECT_FALSE(store.contains(DerivedKind::Specular, kRigId));
    EXPECT_TRUE(store.contains(DerivedKind::Rig, kRigId));
}

// A scene's transfer (binary floats) lives in a folder of its own under the id of its bake.
TEST_F(AssetStoreTest, TransferEntryIsKeptInItsOwnFolder) {
    AssetStore store = open();
    const std::string transfer = std::string("OERPRT\x01\0\0\x80\x3f", 11);
    store.put_derived(DerivedKind::Transfer, kRigId, transfer);
    EXPECT_EQ(store.get_derived(DerivedKind::Transfer, kRigId), transfer);
    EXPECT_FALSE(store.contains(DerivedKind::Rig, kRigId));
    EXPECT_EQ(file_names(folder_ / "transfer"), std::vector<std::string>{kRigId + ".sealed"});
    EXPECT_TRUE(store.remove(DerivedKind::Transfer, kRigId));
    EXPECT_TRUE(file_names(folder_ / "transfer").empty());
}

TEST_F(AssetStoreTest, EmptyPayloadsRoundTrip) {
    AssetStore store = open();
    const std::string id = store.put_source(SourceKind::Mesh, "", "obj");
    EXPECT_EQ(id, "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
    EXPECT_EQ(store.get_source(SourceKind::Mesh, id)->bytes, "");
    store.put_derived(DerivedKind::Rig, kRigId, "");
    EXPECT_EQ(store.get_derived(DerivedKind::Rig, kRigId), "");
}

TEST_F(AssetStoreTest, ASecondStoreOnTheSameFolderSeesTheFirstOnesEntries) {
    {
        AssetStore first = open();
        first.put_source(SourceKind::Environment, "abc", "hdr");
        first.put_derived(DerivedKind::Rig, kRigId, "rig text");
    }
    AssetStore second = open();
    const auto source = second.get_source(SourceKind::Environment, kAbcId);
    ASSERT_TRUE(source.has_value());
    EXPECT_EQ(source->bytes, "abc");
    EXPECT_EQ(source->extension, "hdr");
    EXPECT_EQ(second.get_derived(DerivedKind::Rig, kRigId), "rig text");
    EXPECT_TRUE(log().empty());
}

TEST_F(AssetStoreTest, AbsentEntriesAreNulloptWithoutALogLine) {
    AssetStore store = open();
    EXPECT_FALSE(store.get_source(SourceKind::Mesh, kAbcId).has_value());
    EXPECT_FALSE(store.get_derived(DerivedKind::Rig, kRigId).has_value());
    EXPECT_FALSE(store.contains(SourceKind::Mesh, kAbcId));
    EXPECT_FALSE(store.contains(DerivedKind::Rig, kRigId));
    EXPECT_TRUE(log().empty());
}

TEST_F(AssetStoreTest, RemoveDeletesTheEntryOnce) {
    AssetStore store = open();
    store.put_source(SourceKind::Mesh, "abc", "glb");
    store.put_derived(DerivedKind::Rig, kRigId, "rig");
    EXPECT_TRUE(store.remove(SourceKind::Mesh, kAbcId));
    EXPECT_FALSE(store.remove(SourceKind::Mesh, kAbcId));
    EXPECT_TRUE(store.remove(DerivedKind::Rig, kRigId));
    EXPECT_FALSE(store.remove(DerivedKind::Rig, kRigId));
    EXPECT_FALSE(store.get_source(SourceKind::Mesh, kAbcId).has_value());
    EXPECT_FALSE(store.get_derived(DerivedKind::Rig, kRigId).has_value());
    EXPECT_TRUE(file_names(folder_ / "meshes").empty());
    EXPECT_TRUE(file_names(folder_ / "rigs").empty());
}

// Listings page through a kind's ids in ascending order after a cursor; temporary files,
// other kinds' entries and names that are not entries are not listed.
TEST_F(AssetStoreTest, ListGivesIdsInOrderAfterTheCursorAtMostTheLimit) {
    AssetStore store = open();
    std::vector<std::string> ids;
    for (const std::string bytes : {"a", "b", "c", "d", "e"}) {
        ids.push_back(store.put_source(SourceKind::Mesh, bytes, bytes == "b" ? "obj" : "glb"));
    }
    store.put_source(SourceKind::Environment, "f", "exr");
    store.put_derived(DerivedKind::Rig, kRigId, "rig");
    write_bytes(folder_ / "meshes" / (".tmp-" + ids[0] + ".glb-abc123"), "partial");
    write_bytes(folder_ / "meshes" / "README", "not an entry");
    write_bytes(folder_ / "meshes" / (std::string(64, 'F') + ".glb"), "not an id");
    write_bytes(folder_ / "meshes" / (std::string(64, '0') + ".txt"), "not an extension");
    std::sort(ids.begin(), ids.end());

    EXPECT_EQ(store.list(SourceKind::Mesh, "", 100), ids);
    EXPECT_EQ(store.list(SourceKind::Mesh, "", 2), (std::vector<std::string>{ids[0], ids[1]}));
    EXPECT_EQ(store.list(SourceKind::Mesh, ids[1], 2), (std::vector<std::string>{ids[2], ids[3]}));
    EXPECT_EQ(store.list(SourceKind::Mesh, ids[3], 2), std::vector<std::string>{ids[4]});
    EXPECT_TRUE(store.list(SourceKind::Mesh, ids[4], 2).empty());
    EXPECT_TRUE(store.list(SourceKind::Mesh, "", 0).empty());
    // A cursor need not be stored (its entry may have been removed since).
    EXPECT_EQ(store.list(SourceKind::Mesh, std::string(64, '0'), 1),
              std::vector<std::string>{ids[0]});
    EXPECT_EQ(store.list(SourceKind::Environment, "", 10),
              std::vector<std::string>{api::sha256_hex("f")});
    EXPECT_EQ(store.list(DerivedKind::Rig, "", 10), std::vector<std::string>{kRigId});
    EXPECT_TRUE(store.list(DerivedKind::Specular, "", 10).empty());
    EXPECT_EQ(kind_of_failure([&] { store.list(SourceKind::Mesh, "../etc", 10); }),
              ErrorKind::InvalidInput);
}

TEST_F(AssetStoreTest, InfoGivesSizeExtensionAndTimeOfWriting) {
    AssetStore store = open();
    const auto before = std::chrono::system_clock::now() - std::chrono::seconds(2);
    const std::string id = store.put_source(SourceKind::Environment, "hello", "hdr");
    store.put_derived(DerivedKind::RigSource, kRigId, "record");
    const auto after = std::chrono::system_clock::now() + std::chrono::seconds(2);

    const auto source = store.info(SourceKind::Environment, id);
    ASSERT_TRUE(source.has_value());
    EXPECT_EQ(source->bytes, 5u);
    EXPECT_EQ(source->extension, "hdr");
    EXPECT_GT(source->written, before);
    EXPECT_LT(source->written, after);
    const auto record = store.info(DerivedKind::RigSource, kRigId);
    ASSERT_TRUE(record.has_value());
    EXPECT_EQ(record->bytes, read_bytes(folder_ / "rig-sources" / (kRigId + ".sealed")).size());
    EXPECT_EQ(record->extension, "sealed");
    EXPECT_FALSE(store.info(SourceKind::Mesh, id).has_value());
    EXPECT_FALSE(store.info(DerivedKind::Rig, kRigId).has_value());
    EXPECT_EQ(kind_of_failure([&] { store.info(SourceKind::Mesh, "x"); }), ErrorKind::InvalidInput);
}

TEST_F(AssetStoreTest, SourceWithAFlippedByteIsDetectedDroppedAndLogged) {
    AssetStore store = open();
    const std::string bytes = "a mesh of a few bytes";
    const std::string id = store.put_source(SourceKind::Mesh, bytes, "obj");
    const fs::path path = folder_ / "meshes" / (id + ".obj");
    std::string damaged = bytes;
    damaged[5] ^= 0x01;
    write_bytes(path, damaged);

    EXPECT_FALSE(store.get_source(SourceKind::Mesh, id).has_value());
    EXPECT_FALSE(fs::exists(path));
    EXPECT_FALSE(store.contains(SourceKind::Mesh, id));
    ASSERT_EQ(log().size(), 1u);
    EXPECT_EQ(log()[0], "asset store: removed corrupt " + path.string() +
                            ": its bytes no longer hash to its id");
}

TEST_F(AssetStoreTest, TruncatedSourceIsDetectedAndDropped) {
    AssetStore store = open();
    const std::string id = store.put_source(SourceKind::Environment, "abcdef", "exr");
    const fs::path path = folder_ / "environments" / (id + ".exr");
    fs::resize_file(path, 3);
    EXPECT_FALSE(store.get_source(SourceKind::Environment, id).has_value());
    EXPECT_FALSE(fs::exists(path));
    EXPECT_EQ(log().size(), 1u);
}

TEST_F(AssetStoreTest, SealedEntryWithAFlippedPayloadByteIsDetectedDroppedAndLogged) {
    AssetStore store = open();
    store.put_derived(DerivedKind::Rig, kRigId, "the rig's json");
    const fs::path path = folder_ / "rigs" / (kRigId + ".sealed");
    std::string entry = read_bytes(path);
    entry[entry.size() - 2] ^= 0x20;
    write_bytes(path, entry);

    EXPECT_FALSE(store.get_derived(DerivedKind::Rig, kRigId).has_value());
    EXPECT_FALSE(fs::exists(path));
    ASSERT_EQ(log().size(), 1u);
    EXPECT_EQ(log()[0], "asset store: removed corrupt " + path.string() +
                            ": its payload does not match its SHA-256");
}

TEST_F(AssetStoreTest, TruncatedSealedEntryIsDetectedAndDropped) {
    AssetStore store = open();
    store.put_derived(DerivedKind::Rig, kRigId, "0123456789");
    const fs::path path = folder_ / "rigs" / (kRigId + ".sealed");
    fs::resize_file(path, fs::file_size(path) - 4);

    EXPECT_FALSE(store.get_derived(DerivedKind::Rig, kRigId).has_value());
    EXPECT_FALSE(fs::exists(path));
    ASSERT_EQ(log().size(), 1u);
    EXPECT_EQ(log()[0], "asset store: removed corrupt " + path.string() +
                            ": its payload is 6 bytes, its header says 10");
}

TEST_F(AssetStoreTest, SealedEntryWithADamagedHeaderIsDetectedAndDropped) {
    AssetStore store = open();
    const fs::path path = folder_ / "rigs" / (kRigId + ".sealed");
    const std::string valid = "oer-sealed-v1 " + api::sha256_hex("x") + " 1\nx";
    for (const std::string& damaged :
         {std::string(), std::string("x"), "oer-sealed-v1 " + api::sha256_hex("x") + " 1x\nx",
          "oer-sealed-v2 " + api::sha256_hex("x") + " 1\nx",
          "oer-sealed-v1 " + api::sha256_hex("x") + "\nx", valid.substr(0, 40)}) {
        write_bytes(path, damaged);
        EXPECT_FALSE(store.get_derived(DerivedKind::Rig, kRigId).has_value()) << damaged;
        EXPECT_FALSE(fs::exists(path)) << damaged;
    }
    EXPECT_EQ(log().size(), 6u);
    write_bytes(path, valid);
    EXPECT_EQ(store.get_derived(DerivedKind::Rig, kRigId), "x");
}

TEST_F(AssetStoreTest, ALeftoverTemporaryFileConfusesNothingAndGoesAtALaterStart) {
    const fs::path leftover = folder_ / "meshes" / (".tmp-" + kAbcId + ".glb-Ab12Cd");
    {
        AssetStore store = open();
        write_bytes(leftover, "ab");  // an interrupted write of "abc"
        EXPECT_FALSE(store.contains(SourceKind::Mesh, kAbcId));
        EXPECT_FALSE(store.get_source(SourceKind::Mesh, kAbcId).has_value());
        EXPECT_EQ(store.put_source(SourceKind::Mesh, "abc", "glb"), kAbcId);
        EXPECT_EQ(store.get_source(SourceKind::Mesh, kAbcId)->bytes, "abc");
        EXPECT_TRUE(log().empty());
    }
    // A restart long after the interruption.
    set_untouched_for(leftover, std::chrono::minutes(11));
    AssetStore reopened = open();
    EXPECT_FALSE(fs::exists(leftover));
    EXPECT_EQ(file_names(folder_ / "meshes"), std::vector<std::string>{kAbcId + ".glb"});
    ASSERT_EQ(log().size(), 1u);
    EXPECT_EQ(log()[0], "asset store: removed " + leftover.string() +
                            ", left by an interrupted write (untouched for 11 min)");
    EXPECT_EQ(reopened.get_source(SourceKind::Mesh, kAbcId)->bytes, "abc");
}

// Processes sharing a data folder: a store opened on it (another process starting, or one
// restarting after kill -9) leaves the temporary files of writes that may be in progress,
// those modified within kAbandonedTemporaryAge, and removes older ones.
TEST_F(AssetStoreTest, OpeningASharedFolderSparesAWriteInProgressAndRemovesAnAbandonedOne) {
    AssetStore first = open();
    const fs::path in_progress = folder_ / "meshes" / (".tmp-" + kAbcId + ".glb-Wr1t3s");
    const fs::path abandoned = folder_ / "rigs" / (".tmp-" + kRigId + ".sealed-01dOne");
    write_bytes(in_progress, "a");
    write_bytes(abandoned, "oer-sealed-v1");
    set_untouched_for(in_progress, std::chrono::minutes(9));
    set_untouched_for(abandoned, std::chrono::minutes(11));

    AssetStore second = open();
    EXPECT_TRUE(fs::exists(in_progress));
    EXPECT_FALSE(fs::exists(abandoned));
    EXPECT_EQ(log(), (std::vector<std::string>{
                         "asset store: removed " + abandoned.string() +
                             ", left by an interrupted write (untouched for 11 min)",
                         "asset store: left 1 temporary file(s) modified in the last 10 min: "
                         "writes in progress, perhaps by another process sharing the folder "
                         "(removed at a later start if abandoned)"}));
    // The write in progress completes as write_atomically does, by renaming its file over the
    // entry: the second store reads it.
    write_bytes(in_progress, "abc");
    fs::rename(in_progress, folder_ / "meshes" / (kAbcId + ".glb"));
    EXPECT_EQ(second.get_source(SourceKind::Mesh, kAbcId)->bytes, "abc");
    EXPECT_EQ(first.get_source(SourceKind::Mesh, kAbcId)->bytes, "abc");
}

TEST_F(AssetStoreTest, InvalidIdsAreRejectedBeforeAnyPathIsBuilt) {
    AssetStore store = open();
    const std::string valid(64, 'a');
    const std::vector<std::string> invalid{
        "",
        "../etc/passwd",
        "../" + valid.substr(3),
        std::string(63, 'a'),
        std::string(65, 'a'),
        std::string(64, 'A'),
        valid.substr(0, 63) + 'g',
        valid.substr(0, 32) + std::string(1, '\0') + valid.substr(33),
        valid.substr(0, 63) + '/',
    };
    EXPECT_TRUE(is_asset_id(valid));
    for (const std::string& id : invalid) {
        EXPECT_FALSE(is_asset_id(id));
        const std::vector<std::function<void()>> operations{
            [&] { store.get_source(SourceKind::Mesh, id); },
            [&] { store.get_derived(DerivedKind::Rig, id); },
            [&] { store.put_derived(DerivedKind::Rig, id, "x"); },
            [&] { store.contains(SourceKind::Environment, id); },
            [&] { store.contains(DerivedKind::Rig, id); },
            [&] { store.remove(SourceKind::Mesh, id); },
            [&] { store.remove(DerivedKind::Rig, id); },
        };
        for (const auto& operation : operations) {
            EXPECT_EQ(kind_of_failure(operation), ErrorKind::InvalidInput);
        }
    }
    EXPECT_EQ(file_names(folder_.parent_path()), std::vector<std::string>{"data"});
    EXPECT_EQ(file_names(folder_),
              (std::vector<std::string>{"environments", "mesh-summaries", "meshes", "rig-sources",
                                        "rigs", "specular", "transfer", "transfer-meshes"}));
    for (const char* kind : {"environments", "meshes", "rig-sources", "rigs"}) {
        EXPECT_TRUE(file_names(folder_ / kind).empty()) << kind;
    }
}

TEST_F(AssetStoreTest, ExtensionsComeFromAFixedListPerKind) {
    AssetStore store = open();
    for (const char* extension : {"", "GLB", ".glb", "exe", "glb/../x", "exr"}) {
        EXPECT_EQ(kind_of_failure([&] { store.put_source(SourceKind::Mesh, "abc", extension); }),
                  ErrorKind::Unsupported)
            << extension;
    }
    EXPECT_EQ(kind_of_failure([&] { store.put_source(SourceKind::Environment, "abc", "obj"); }),
              ErrorKind::Unsupported);
    EXPECT_TRUE(file_names(folder_ / "meshes").empty());
    EXPECT_TRUE(file_names(folder_ / "environments").empty());
    const auto meshes = allowed_extensions(SourceKind::Mesh);
    EXPECT_EQ(std::vector<std::string_view>(meshes.begin(), meshes.end()),
              (std::vector<std::string_view>{"glb", "gltf", "obj"}));
    const auto environments = allowed_extensions(SourceKind::Environment);
    EXPECT_EQ(std::vector<std::string_view>(environments.begin(), environments.end()),
              (std::vector<std::string_view>{"exr", "hdr", "png", "jpg", "jpeg", "tif", "tiff"}));
}

TEST_F(AssetStoreTest, ConcurrentPutsAndGetsOfSharedAndOwnEntries) {
    AssetStore store = open();
    const std::string shared(100'000, 's');
    const std::string shared_id = api::sha256_hex(shared);
    constexpr int kThreads = 8, kRounds = 25;
    std::vector<int> failures(kThreads, 0);
    std::vector<std::thread> threads;
    for (int t = 0; t < kThreads; ++t) {
        threads.emplace_back([&, t] {
            for (int round = 0; round < kRounds; ++round) {
                const std::string own =
                    "thread " + std::to_string(t) + " round " + std::to_string(round);
                const std::string own_id = store.put_source(SourceKind::Mesh, own, "obj");
                failures[t] += store.put_source(SourceKind::Mesh, shared, "glb") != shared_id;
                store.put_derived(DerivedKind::Rig, shared_id, shared);
                const auto own_back = store.get_source(SourceKind::Mesh, own_id);
                const auto shared_back = store.get_source(SourceKind::Mesh, shared_id);
                const auto rig_back = store.get_derived(DerivedKind::Rig, shared_id);
                failures[t] += !own_back || own_back->bytes != own;
                failures[t] += !shared_back || shared_back->bytes != shared;
                failures[t] += rig_back != shared;
            }
        });
    }
    for (auto& thread : threads) {
        thread.join();
    }
    EXPECT_EQ(std::count(failures.begin(), failures.end(), 0), kThreads);
    EXPECT_TRUE(log().empty());
    EXPECT_EQ(file_names(folder_ / "meshes").size(), std::size_t(kThreads * kRounds + 1));
    EXPECT_EQ(file_names(folder_ / "rigs"), std::vector<std::string>{shared_id + ".sealed"});
}
